// Shared by the module's files: errors as plimsoll.Error, and the runtime's bindings.
#pragma once

#include "plimsoll/core/result.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <variant>
#include <string>

namespace plimsoll::python {

/// Raises plimsoll.Error with the error's message and kind.
[[noreturn]] void raise(const Error& error);
/// Raises plimsoll.Error with this message and kind name.
[[noreturn]] void raise(const std::string& message, const char* kind);

/// The value of a Result, or plimsoll.Error.
template <class T>
T value(Result<T>&& result) {
    if (!result) raise(result.error());
    return std::move(*result);
}

/// Metres per file unit from an optional argument (None: the file's own unit).
/// A mesh's unit from Python: a name ("cm", as --unit takes it), metres per file unit, or None
/// (the file's own unit).
using Unit = std::optional<std::variant<double, std::string>>;
double unitScale(const Unit& unit);

/// plimsoll.Bundle, plimsoll.Instance, plimsoll.Simulation (runtime.cpp).
void bindRuntime(pybind11::module_& m);

}  // namespace plimsoll::python
