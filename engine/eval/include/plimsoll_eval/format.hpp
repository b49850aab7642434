// The runtime bundle's format facts, read by the runtime library and written by the engine's
// exporter (docs/bundle.md). Change them here and both follow.
#pragma once

namespace plimsoll_eval {

inline constexpr const char* kBundleFormat = "plimsoll-runtime-bundle";  ///< manifest "format"
inline constexpr int kBundleSchemaMajor = 1;  ///< readers refuse any other major
inline constexpr int kBundleSchemaMinor =
    6;  ///< newest minor (older minors are read too; 3 added "radiation", 4 "world", 5
        ///< "world.simulation.sleep", 6 "levels")

inline constexpr const char* kManifestFile = "manifest.json";
inline constexpr const char* kSamplesFile = "samples.exr";
inline constexpr const char* kGraphFile = "graph.json";
inline constexpr int kGraphSchemaVersion = 1;  ///< graph.json's "schema_version" (docs/formats.md)
inline constexpr const char* kTexelNodesFile = "texel_nodes.exr";

/// A compact bundle's manifest `sample_encoding.type` and its samples.exr channels (x, y
/// float32, the rest HALF; docs/bundle.md "Compact bundles").
inline constexpr const char* kCompactSampleEncoding = "half_scaled";
inline constexpr const char* kCompactSampleChannels[] = {"x",   "y",   "hpx", "hpy",   "hpz",
                                                         "hax", "hay", "haz", "harea", "coverage"};

}  // namespace plimsoll_eval
