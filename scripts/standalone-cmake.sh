# Sourced by the scripts that configure the runtime on its own (test-runtime-install.sh,
# test-determinism.sh): CMake's generator and compiler launcher as the main build uses them,
# Ninja and ccache where installed, as arrays to splice into a cmake command line.
generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
