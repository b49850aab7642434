// The renderer's GLSL sources, kept as files in render/shaders/ and compiled into the binary by
// cmake/embed_shaders.cmake (as the OpenCL kernels are): one symbol per file, named after it
// ("mesh.vert" -> mesh_vert).
#pragma once

namespace plimsoll::editor::shaders {

extern const char* const mesh_vert;  ///< bodies: world position and uv
extern const char* const mesh_frag;  ///< flat shading, overlay texture or base colour
extern const char* const line_vert;  ///< lines: a colour per vertex
extern const char* const line_frag;
extern const char* const water_view_vert;  ///< waterSides(), linked into the others
extern const char* const water_view_frag;  ///< throughWater(), linked into the others
extern const char* const graph_node_vert;  ///< water-graph nodes
extern const char* const graph_node_frag;  ///< filled with water up to the node's level

}  // namespace plimsoll::editor::shaders
