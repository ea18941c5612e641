// Results of calls that can fail for reasons a user can act on (bad input, no device, a refused
// submission, a driver out of memory). Programmer errors inside the library use assertions instead.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace wrsfov {

/// An error: a machine-readable code (an enum of the calling module, stored as int) and a message.
struct Error {
    int code = 0;
    std::string message;
};

/// Either a value or an Error. Deliberately small: `ok()`, `value()`, `error()`.
template <typename T>
class Result {
public:
    Result(T value) : v_(std::move(value)) {}
    Result(Error error) : v_(std::move(error)) {}
    bool ok() const { return v_.index() == 0; }
    explicit operator bool() const { return ok(); }
    T& value() { return std::get<0>(v_); }
    const T& value() const { return std::get<0>(v_); }
    T& operator*() { return value(); }
    T* operator->() { return &value(); }
    const Error& error() const { return std::get<1>(v_); }

private:
    std::variant<T, Error> v_;
};

/// Success or an Error, for calls without a value.
class Status {
public:
    Status() = default;
    Status(Error error) : error_(std::move(error)), ok_(false) {}
    static Status success() { return {}; }
    bool ok() const { return ok_; }
    explicit operator bool() const { return ok_; }
    const Error& error() const { return error_; }
    const std::string& message() const { return error_.message; }

private:
    Error error_;
    bool ok_ = true;
};

}  // namespace wrsfov
