// Linked into the executables of the sanitizer build only (PLIMSOLL_SANITIZE): dlclose does
// nothing, so every library loaded at run time stays mapped until exit.
//
// Why: Mesa's EGL and GLX loaders dlclose the llvmpipe driver (swrast_dri.so) at
// eglTerminate. Blocks the driver still points to from its own data then look unreachable
// to LeakSanitizer, which reports them as leaks from "<unknown module>" that no suppression
// can name. With the driver kept loaded the same runs report nothing. Keeping libraries
// mapped hides no leak of ours: what they point to stays reachable, as it was before the
// dlclose.
extern "C" int dlclose(void*) { return 0; }
