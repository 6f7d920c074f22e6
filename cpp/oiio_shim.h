/* prism ↔ OpenImageIO shim: a C ABI with plain types only.
 *
 * Every function returns 0 on success and non-zero on failure; on failure a one-line,
 * NUL-terminated message is written into the caller's `err` buffer (truncated to `err_len`).
 * No C++ exception ever crosses this boundary. */
#ifndef PRISM_OIIO_SHIM_H
#define PRISM_OIIO_SHIM_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Pixel storage format in the file. */
enum prism_oiio_format {
    PRISM_OIIO_HALF = 0,
    PRISM_OIIO_FLOAT = 1,
    PRISM_OIIO_UINT8 = 2,
    PRISM_OIIO_UINT16 = 3,
    PRISM_OIIO_OTHER = 4 /* only reported by prism_oiio_read_info */
};

/* A header attribute: `name` (OpenImageIO's name for it) and its value, by `type`. */
enum prism_oiio_attr_type {
    PRISM_OIIO_ATTR_FLOAT = 0,  /* values[0] */
    PRISM_OIIO_ATTR_INT = 1,    /* int_value */
    PRISM_OIIO_ATTR_STRING = 2, /* text */
    PRISM_OIIO_ATTR_M44F = 3,   /* values[0..16], row by row */
    PRISM_OIIO_ATTR_FLOAT8 = 4  /* values[0..8] (OpenEXR's chromaticities: rx ry gx gy bx by wx wy) */
};

struct prism_oiio_attr {
    const char *name;
    int type;
    const float *values;
    int int_value;
    const char *text;
};

/* Writes `width`×`height`×`channels` interleaved floats (row-major, top row first) to `path`,
 * stored as `format`; the file type comes from the extension. Integer formats are clamped to
 * [0,1] and rounded; no transfer curve is applied here (the caller encodes first).
 * `quality` (1–100) is used by lossy formats such as JPEG; 0 keeps OIIO's default.
 * `window` (4 ints, may be NULL): x, y of the image's first pixel in a larger image of size
 * window[2]×window[3] — the image is stored as that data window inside that display window
 * (formats that have them); a zero size means the image is whole. */
/* `attrs` (`attr_count` of them, may be NULL when 0) go into the file's header where its format
 * has a place for them. */
int prism_oiio_write_meta(const char *path, int width, int height, int channels,
                          const float *pixels, int format, int quality, const int *window,
                          const struct prism_oiio_attr *attrs, int attr_count, char *err,
                          size_t err_len);

/* Reports the size, channel count and stored pixel format of the first subimage of `path`. */
int prism_oiio_read_info(const char *path, int *width, int *height, int *channels, int *format,
                         char *err, size_t err_len);

/* Reads the first subimage of `path` as floats into `pixels`, which must hold exactly
 * `width*height*channels` values matching prism_oiio_read_info; integer formats come back
 * normalised to [0,1] without any transfer curve removed, alpha unassociated. */
int prism_oiio_read(const char *path, int width, int height, int channels, float *pixels,
                    size_t pixel_count, char *err, size_t err_len);

#ifdef __cplusplus
}
#endif

#endif
