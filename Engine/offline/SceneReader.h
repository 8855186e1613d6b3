#pragma once
// How a scene file is read (Scene.cpp, SceneObstacles.cpp): a JSON object's fields taken by name
// and checked, each error naming its path. OFF.

#include "offline/Scene.h"

#include <nlohmann/json.hpp>

#include <initializer_list>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace jawari::scene_reading
{
using json = nlohmann::json;

inline std::string show(double v)
{
    std::ostringstream s;
    s.precision(12);
    s << v;
    return s.str();
}

inline std::string typeName(const json& j)
{
    return j.type_name();
}

// A JSON object being read at a path: takes the fields it knows, then rejects the rest.
class ObjectReader
{
public:
    ObjectReader(const json& object, std::string path)
        : object_(object)
        , path_(std::move(path))
    {
        if (!object_.is_object())
            throw SceneError(path_.empty() ? "(top level)" : path_, "must be an object, got " + typeName(object_));
    }

    std::string at(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
    bool has(const std::string& key) const { return object_.contains(key); }
    const json& raw(const std::string& key)
    {
        seen_.insert(key);
        return object_.at(key);
    }

    // Optional number: stays `fallback` when absent. Must be finite.
    double number(const std::string& key, double fallback)
    {
        if (!has(key))
            return fallback;
        const json& v = raw(key);
        if (!v.is_number())
            throw SceneError(at(key), "must be a number, got " + typeName(v));
        const double d = v.get<double>();
        if (!std::isfinite(d))
            throw SceneError(at(key), "must be finite");
        return d;
    }
    double positive(const std::string& key, double fallback)
    {
        const double d = number(key, fallback);
        if (!(d > 0.0))
            throw SceneError(at(key), "must be > 0 (got " + show(d) + ")");
        return d;
    }
    bool boolean(const std::string& key, bool fallback)
    {
        if (!has(key))
            return fallback;
        const auto& v = raw(key);
        if (!v.is_boolean())
            throw SceneError(at(key), "must be true or false, got " + typeName(v));
        return v.get<bool>();
    }
    double nonNegative(const std::string& key, double fallback)
    {
        const double d = number(key, fallback);
        if (!(d >= 0.0))
            throw SceneError(at(key), "must be >= 0 (got " + show(d) + ")");
        return d;
    }
    std::optional<long long> integer(const std::string& key)
    {
        if (!has(key))
            return std::nullopt;
        const json& v = raw(key);
        if (v.is_number_integer())
            return v.get<long long>();
        if (v.is_number_float())
        {
            const double d = v.get<double>();
            if (std::isfinite(d) && d == std::floor(d) && std::abs(d) < 9e15)
                return static_cast<long long>(d);
        }
        throw SceneError(at(key),
                         "must be a whole number, got " + (v.is_number() ? show(v.get<double>()) : typeName(v)));
    }
    std::string string(const std::string& key, const std::string& fallback, std::initializer_list<const char*> allowed)
    {
        return string(key, fallback, std::vector<const char*>(allowed));
    }
    std::string string(const std::string& key, const std::string& fallback, const std::vector<const char*>& allowed)
    {
        if (!has(key))
            return fallback;
        const json& v = raw(key);
        if (!v.is_string())
            throw SceneError(at(key), "must be a string, got " + typeName(v));
        const auto s = v.get<std::string>();
        std::string list;
        for (const char* a : allowed)
        {
            if (s == a)
                return s;
            list += list.empty() ? std::string("'") + a + "'" : std::string(", '") + a + "'";
        }
        throw SceneError(at(key), "unknown value '" + s + "' (expected one of " + list + ")");
    }
    std::vector<double> numbers(const std::string& key)
    {
        const json& v = raw(key);
        if (!v.is_array())
            throw SceneError(at(key), "must be an array of numbers, got " + typeName(v));
        std::vector<double> out;
        for (size_t i = 0; i < v.size(); ++i)
        {
            const std::string here = at(key) + "[" + std::to_string(i) + "]";
            if (!v[i].is_number())
                throw SceneError(here, "must be a number, got " + typeName(v[i]));
            const double d = v[i].get<double>();
            if (!std::isfinite(d))
                throw SceneError(here, "must be finite");
            out.push_back(d);
        }
        return out;
    }

    void rejectUnknown() const
    {
        for (auto it = object_.begin(); it != object_.end(); ++it)
            if (!seen_.count(it.key()) && !known_.count(it.key()))
                throw SceneError(at(it.key()), "unknown field");
    }
    void allow(std::initializer_list<const char*> keys)
    {
        for (const char* k : keys)
            known_.insert(k);
    }

private:
    const json& object_;
    std::string path_;
    std::set<std::string> seen_;
    std::set<std::string> known_;
};

// x strictly inside (0, L), or a SceneError at `path`.
void requireOnString(const std::string& path, double x, double L);

// The obstacles array, threads laid across the bridges before them (SceneObstacles.cpp).
void readObstacles(const json& obs, Scene& scene);

// The body object (SceneBody.cpp): a factory body by name or listed modes; the obstacles on it.
SceneBody readBody(const json& value, const Scene& scene);
// The body's rules after overrides: its obstacles exist and its modes are sound, "pressure" needs
// it; the reference reads "bridge_force".
void validateSceneBody(const Scene& scene);

}  // namespace jawari::scene_reading
