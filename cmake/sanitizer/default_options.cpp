// Linked into the executables of the sanitizer build only (PLIMSOLL_SANITIZE): options the
// sanitizer runtime takes before ASAN_OPTIONS, so a test run by hand from build-asan/ behaves
// as scripts/test-sanitized.sh runs it (the environment still overrides any of them).
//
// intercept_tls_get_addr=0: up to GCC 13 (Debian 12 has 12) the runtime's __tls_get_addr
// interceptor takes a dynamic TLS block whose start lies sizeof(Glibc_2_19_tls_header) past a
// page boundary for one with a pre-2.25 glibc header and reads the two words before it as an
// address and a length. Since glibc 2.25 no such header exists; an ordinary block lands there
// by chance, and LeakSanitizer's tracer then dies at exit ("Tracer caught signal 11") with no
// leak to report. PoCL and its LLVM use dynamic TLS, and the OpenCL fault-injection tests hit
// that placement on every run in CI. Without the interceptor a dynamic TLS block is an ordinary
// heap block, reached through the thread's DTV from its static TLS, which is still scanned.
// (LLVM 17 dropped the pre-2.25 guess; Mudlet/Mudlet#9809 traced the crash to it.)
extern "C" const char* __asan_default_options() { return "intercept_tls_get_addr=0"; }
