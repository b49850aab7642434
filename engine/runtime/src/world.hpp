// The manifest's "world" (schema 1.4), read by the loader (bundle.cpp).
#pragma once

#include "plimsoll_runtime/runtime.hpp"

#include "json.hpp"
#include "vec.hpp"

#include <string>

namespace plimsoll_runtime {

/// Fills `out` from the manifest's "world" (left at its defaults, present false, when the
/// manifest has none); false with `error` naming `file` and the JSON path on a bad value.
bool readBundleWorld(const json::Value& manifest, const std::string& file, BundleWorld& out,
                     std::string& error);

}  // namespace plimsoll_runtime
