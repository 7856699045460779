// Status: the error value every layer returns for anything a user or a file can cause.
// Programmer mistakes are asserts; exceptions never cross a layer boundary (house style 7).
#pragma once

#include <string>
#include <utility>

namespace sculpt {

struct Status {
    bool ok = true;
    std::string message;  // human-readable, names what is wrong; empty when ok

    static Status success() { return {}; }
    static Status error(std::string why) { return Status{false, std::move(why)}; }
    explicit operator bool() const { return ok; }
};

}  // namespace sculpt
