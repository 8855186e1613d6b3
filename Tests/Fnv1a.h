#pragma once
// FNV-1a, 64 bits, over bytes: the tests' fingerprint of a render (ChecksumTests) or of a stored
// file's samples (StoredReference.h), equal only when every bit is.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace jawari::test
{

struct Fnv1a
{
    uint64_t value = 1469598103934665603ull;
    void add(const void* data, size_t bytes)
    {
        const auto* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < bytes; ++i)
            value = (value ^ p[i]) * 1099511628211ull;
    }
    void add(const std::vector<double>& v) { add(v.data(), v.size() * sizeof(double)); }
};

}  // namespace jawari::test
