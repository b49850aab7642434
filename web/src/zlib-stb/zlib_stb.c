/* zlib's inflate API over stb_image's decoder: see zlib.h beside this file. */
#include "zlib.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG /* the zlib decoder comes with the PNG reader */
#define STBI_NO_STDIO
#define STBI_NO_LINEAR
#define STBI_NO_HDR
#define STBI_NO_FAILURE_STRINGS
#include <stb/stb_image.h>

/* stb does not check the stream's Adler-32; zlib does, so the shim does too. */
static int adler32_matches(const unsigned char* data, size_t size, const unsigned char* stream,
                           size_t streamSize) {
    if (streamSize < 6) return 0;
    unsigned long a = 1, b = 0;
    for (size_t i = 0; i < size; ++i) {
        a = (a + data[i]) % 65521u;
        b = (b + a) % 65521u;
    }
    const unsigned char* t = stream + streamSize - 4;
    const unsigned long stored = ((unsigned long)t[0] << 24) | ((unsigned long)t[1] << 16) |
                                 ((unsigned long)t[2] << 8) | (unsigned long)t[3];
    return ((b << 16) | a) == stored;
}

typedef struct {
    char* data;
    size_t size, given;
    int inflated;
} shim_state;

int inflateInit(z_streamp strm) {
    if (!strm) return Z_STREAM_ERROR;
    shim_state* s = (shim_state*)calloc(1, sizeof(shim_state));
    if (!s) return Z_MEM_ERROR;
    strm->state = s;
    strm->total_in = strm->total_out = 0;
    return Z_OK;
}

int inflate(z_streamp strm, int flush) {
    (void)flush;
    if (!strm || !strm->state) return Z_STREAM_ERROR;
    shim_state* s = (shim_state*)strm->state;
    if (!s->inflated) {
        if (strm->avail_in > INT_MAX) return Z_DATA_ERROR;
        int length = 0;
        const int guess =
            strm->avail_in < (1u << 20) ? (int)strm->avail_in * 4 + 1024 : (int)strm->avail_in;
        s->data = stbi_zlib_decode_malloc_guesssize_headerflag(
            (const char*)strm->next_in, (int)strm->avail_in, guess, &length, 1);
        s->inflated = 1;
        if (!s->data) return Z_DATA_ERROR;
        s->size = (size_t)length;
        if (!adler32_matches((const unsigned char*)s->data, s->size, strm->next_in,
                             strm->avail_in)) {
            free(s->data);
            s->data = NULL;
            return Z_DATA_ERROR;
        }
        strm->total_in += strm->avail_in;
        strm->next_in += strm->avail_in;
        strm->avail_in = 0;
    }
    if (!s->data) return Z_DATA_ERROR;
    const size_t left = s->size - s->given;
    if (left == 0) return Z_BUF_ERROR;
    const size_t n = left < strm->avail_out ? left : strm->avail_out;
    memcpy(strm->next_out, s->data + s->given, n);
    s->given += n;
    strm->next_out += n;
    strm->avail_out -= (uInt)n;
    strm->total_out += n;
    return s->given == s->size ? Z_STREAM_END : Z_OK;
}

int inflateEnd(z_streamp strm) {
    if (!strm || !strm->state) return Z_STREAM_ERROR;
    shim_state* s = (shim_state*)strm->state;
    free(s->data);
    free(s);
    strm->state = NULL;
    return Z_OK;
}

int uncompress(Bytef* dest, uLongf* destLen, const Bytef* source, uLong sourceLen) {
    if (*destLen > INT_MAX || sourceLen > INT_MAX) return Z_BUF_ERROR;
    const int n =
        stbi_zlib_decode_buffer((char*)dest, (int)*destLen, (const char*)source, (int)sourceLen);
    if (n < 0) return Z_DATA_ERROR;
    if (!adler32_matches(dest, (size_t)n, source, sourceLen)) return Z_DATA_ERROR;
    *destLen = (uLongf)n;
    return Z_OK;
}

uLong compressBound(uLong sourceLen) {
    return sourceLen + (sourceLen >> 12) + (sourceLen >> 14) + 64;
}

int compress(Bytef* dest, uLongf* destLen, const Bytef* source, uLong sourceLen) {
    (void)dest;
    (void)destLen;
    (void)source;
    (void)sourceLen;
    return Z_STREAM_ERROR;
}

uLong crc32(uLong crc, const Bytef* buf, uInt len) {
    if (!buf) return 0;
    unsigned long c = crc ^ 0xFFFFFFFFul;
    for (uInt i = 0; i < len; ++i) {
        c ^= buf[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320ul & (0ul - (c & 1ul)));
    }
    return c ^ 0xFFFFFFFFul;
}
