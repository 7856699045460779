// Reading JSON fields with errors that name the field path (shared by the script and lattice readers).
// Internal to io: a parse failure throws FieldError, which each reader's entry point turns into a Status.
#pragma once

#include <array>
#include <cmath>
#include <initializer_list>
#include <set>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace sculpt::io::json_fields {

using nlohmann::json;

struct FieldError {
    std::string path;
    std::string what;
};

[[noreturn]] inline void fail(const std::string& path, const std::string& what) { throw FieldError{path, what}; }

inline void allowOnly(const json& object, const std::string& path, std::initializer_list<const char*> keys) {
    if (!object.is_object()) fail(path, "expected an object");
    const std::set<std::string> allowed(keys.begin(), keys.end());
    for (auto it = object.begin(); it != object.end(); ++it)
        if (!allowed.count(it.key())) fail(path + "." + it.key(), "unknown field");
}

inline const json& required(const json& object, const char* key, const std::string& path) {
    if (!object.contains(key)) fail(path + "." + key, "missing");
    return object[key];
}

inline double number(const json& value, const std::string& path) {
    if (!value.is_number()) fail(path, "expected a number");
    const double d = value.get<double>();
    if (!std::isfinite(d)) fail(path, "expected a finite number");
    return d;
}

inline int integer(const json& value, const std::string& path) {
    if (!value.is_number_integer()) fail(path, "expected an integer");
    const auto i = value.get<long long>();
    if (i < -1000000000LL || i > 1000000000LL) fail(path, "integer out of range");
    return static_cast<int>(i);
}

inline Eigen::Vector3d vector3(const json& value, const std::string& path) {
    if (!value.is_array() || value.size() != 3) fail(path, "expected an array of 3 numbers");
    return {number(value[0], path + "[0]"), number(value[1], path + "[1]"), number(value[2], path + "[2]")};
}

inline Eigen::Vector2d vector2(const json& value, const std::string& path) {
    if (!value.is_array() || value.size() != 2) fail(path, "expected an array of 2 numbers");
    return {number(value[0], path + "[0]"), number(value[1], path + "[1]")};
}

template <int N>
std::array<int, N> intArray(const json& value, const std::string& path) {
    if (!value.is_array() || value.size() != N) fail(path, "expected an array of " + std::to_string(N) + " integers");
    std::array<int, N> out{};
    for (int i = 0; i < N; ++i) out[i] = integer(value[i], path + "[" + std::to_string(i) + "]");
    return out;
}

inline std::array<int, 3> int3(const json& value, const std::string& path) { return intArray<3>(value, path); }

inline std::string text(const json& value, const std::string& path) {
    if (!value.is_string()) fail(path, "expected a string");
    return value.get<std::string>();
}

inline bool boolean(const json& value, const std::string& path) {
    if (!value.is_boolean()) fail(path, "expected true or false");
    return value.get<bool>();
}

inline json vectorJson(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

}  // namespace sculpt::io::json_fields
