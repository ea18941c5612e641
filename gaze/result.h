// A value or an error message a user can act on.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace wrsfov::gaze {

/// Why an operation failed, worded for the person who has to fix it.
struct Error {
    std::string message;
};

/// Either a `T` or an `Error`. Accessing the wrong alternative throws `std::bad_variant_access`.
template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : v_(std::move(value)) {}
    Result(Error error) : v_(std::move(error)) {}

    bool ok() const { return v_.index() == 0; }
    explicit operator bool() const { return ok(); }

    T& value() & { return std::get<0>(v_); }
    const T& value() const& { return std::get<0>(v_); }
    T&& value() && { return std::get<0>(std::move(v_)); }
    T* operator->() { return &std::get<0>(v_); }
    const T* operator->() const { return &std::get<0>(v_); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }

    const Error& error() const { return std::get<1>(v_); }

private:
    std::variant<T, Error> v_;
};

/// Success without a value.
struct Ok {};
using Status = Result<Ok>;

/// Shorthand for returning an error.
inline Error fail(std::string message) { return Error{std::move(message)}; }

}  // namespace wrsfov::gaze
