/* The part of zlib's API the runtime uses (png.cpp inflates row by row; tinyexr's ZIP images
 * call uncompress), implemented over stb_image's zlib decoder (Debian's libstb-dev) for the
 * WebAssembly build. Emscripten's own zlib port downloads zlib's sources on first use; this
 * shim needs nothing beyond what the build machine has. The native build links the real zlib:
 * this header is on the include path of the web build only (web/CMakeLists.txt).
 * Inflating and CRC-32 only: compress() fails (the runtime never writes EXR). Like zlib, the
 * stream's Adler-32 checksum is checked. */
#ifndef PLIMSOLL_WEB_ZLIB_STB_H
#define PLIMSOLL_WEB_ZLIB_STB_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef unsigned char Bytef;
typedef unsigned int uInt;
typedef unsigned long uLong;
typedef unsigned long uLongf;

#define Z_OK 0
#define Z_STREAM_END 1
#define Z_NO_FLUSH 0
#define Z_STREAM_ERROR (-2)
#define Z_DATA_ERROR (-3)
#define Z_MEM_ERROR (-4)
#define Z_BUF_ERROR (-5)

typedef struct z_stream_s {
    const Bytef* next_in;
    uInt avail_in;
    uLong total_in;
    Bytef* next_out;
    uInt avail_out;
    uLong total_out;
    void* state; /* the whole inflated stream and how much of it was handed out */
} z_stream;
typedef z_stream* z_streamp;

int inflateInit(z_streamp strm);
/* The first call inflates all of next_in (the caller gives the whole stream at once, as the
 * runtime does); each call then copies what fits into next_out: Z_OK while more remains,
 * Z_STREAM_END once it is all out, Z_BUF_ERROR when nothing is left, Z_DATA_ERROR for a
 * corrupt stream or a wrong checksum. */
int inflate(z_streamp strm, int flush);
int inflateEnd(z_streamp strm);

/* CRC-32 (PNG's chunk check), as zlib's: crc32(0, data, n) for a fresh one. */
uLong crc32(uLong crc, const Bytef* buf, uInt len);

int uncompress(Bytef* dest, uLongf* destLen, const Bytef* source, uLong sourceLen);
uLong compressBound(uLong sourceLen);
int compress(Bytef* dest, uLongf* destLen, const Bytef* source, uLong sourceLen);

#ifdef __cplusplus
}
#endif

#endif
