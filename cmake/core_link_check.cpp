// Linked with every object of plimsoll_core and nothing but the core's own dependencies
// (engine/CMakeLists.txt): the link fails if a core source calls into another engine library
// (file formats, OpenCL, CGAL), which the core's link list alone would not show.
int main() { return 0; }
