#pragma once
// A table (a std::vector that stepping only reads) whose copy is skipped when the destination
// already holds the same values. Every change goes through edit(), which gives the table a new
// stamp, unique in the process; a copy takes the source's values and stamp together. So two tables
// with one stamp hold the same values, and copying a voice into its backup, which it does every
// chunk with a second core, copies only the tables changed since the last copy (a retune, a
// release, a new law), not all of them.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace jawari
{

namespace detail
{
inline uint64_t nextTableStamp()
{
    static std::atomic<uint64_t> last{0};  // lock-free: RT
    return last.fetch_add(1, std::memory_order_relaxed) + 1;
}
}  // namespace detail

template <typename T>
class StampedVector
{
public:
    StampedVector() = default;
    StampedVector(const StampedVector&) = default;
    StampedVector(StampedVector&&) noexcept = default;
    StampedVector& operator=(StampedVector&&) noexcept = default;
    // RT when this holds as many values (no allocation): the values, unless this has them already.
    StampedVector& operator=(const StampedVector& other)
    {
        if (stamp_ != other.stamp_ || values_.size() != other.values_.size())
        {
            values_ = other.values_;
            stamp_ = other.stamp_;
        }
        return *this;
    }

    StampedVector& operator=(const std::vector<T>& values)  // OFF (it may allocate)
    {
        edit() = values;
        return *this;
    }

    // RT: the values to change, under a new stamp. Take it afresh for each change: a reference
    // kept across a copy would change the values under the old stamp.
    std::vector<T>& edit()
    {
        stamp_ = detail::nextTableStamp();
        return values_;
    }

    const std::vector<T>& values() const { return values_; }
    operator const std::vector<T>&() const { return values_; }
    const T& operator[](size_t i) const { return values_[i]; }
    const T* data() const { return values_.data(); }
    size_t size() const { return values_.size(); }
    bool empty() const { return values_.empty(); }
    auto begin() const { return values_.begin(); }
    auto end() const { return values_.end(); }

private:
    std::vector<T> values_;
    uint64_t stamp_ = 0;  // 0: never edited (empty)
};

}  // namespace jawari
