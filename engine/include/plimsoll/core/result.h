// Result<T>: the return type of everything that can fail at run time (a bad file, a broken
// mesh, a missing device). Asserts are for programmer misuse only; exceptions never cross the
// engine's public API.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace plimsoll {

/// What class of failure an Error is: what a caller branches on (retry, fall back, report) and
/// what tests compare, so that rewording a message never breaks a caller.
enum class ErrorKind {
    io,               ///< a file or folder could not be opened, read, written or renamed
    format,           ///< bytes that do not parse as the format they claim (mesh, image, JSON)
    schema,           ///< well-formed JSON or data whose content breaks the schema (types, ranges)
    limit,            ///< a size beyond a documented limit (limits.h), refused before allocating
    device,           ///< a compute device is missing, lost or out of resources
    kernelBuild,      ///< OpenCL kernels failed to compile or link for a device
    invalidArgument,  ///< an argument or option outside its domain (NaN, negative size, unknown id)
    unsupported,      ///< this build or input lacks a capability (a configure option turned off)
};

/// The kind's name as messages and JSON print it ("io", "kernel-build", ...).
constexpr const char* errorKindName(ErrorKind kind) {
    switch (kind) {
        case ErrorKind::io:
            return "io";
        case ErrorKind::format:
            return "format";
        case ErrorKind::schema:
            return "schema";
        case ErrorKind::limit:
            return "limit";
        case ErrorKind::device:
            return "device";
        case ErrorKind::kernelBuild:
            return "kernel-build";
        case ErrorKind::invalidArgument:
            return "invalid-argument";
        case ErrorKind::unsupported:
            return "unsupported";
    }
    return "error";
}

/// What went wrong, in words a user can act on (names the file and the problem), and its kind:
/// every error has one.
struct Error {
    Error(std::string message, ErrorKind kind) : message(std::move(message)), kind(kind) {}
    std::string message;
    ErrorKind kind;
};

template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : state_(std::move(value)) {}
    Result(Error error) : state_(std::move(error)) {}

    bool ok() const { return state_.index() == 0; }
    explicit operator bool() const { return ok(); }

    T& value() & { return std::get<0>(state_); }
    const T& value() const& { return std::get<0>(state_); }
    T&& value() && { return std::get<0>(std::move(state_)); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }

    const Error& error() const { return std::get<1>(state_); }

private:
    std::variant<T, Error> state_;
};

/// Result of an operation that returns nothing but can fail.
struct Ok {};
using Status = Result<Ok>;

inline Error makeError(ErrorKind kind, std::string message) {
    return Error{std::move(message), kind};
}
/// The same error with context in front of its message ("body 'hull': "), its kind kept.
inline Error withContext(const std::string& context, const Error& error) {
    return Error{context + error.message, error.kind};
}

}  // namespace plimsoll
