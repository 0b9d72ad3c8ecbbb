/* testutil.h - shared helpers for the cmocka tests: paths, temporary files, float checks, bit-for-bit
 * comparison of images and texel buffers (the determinism tests: thread counts, tile sizes, paths),
 * environments made of a function, and a rasterized G-buffer in one call.
 * Tests run from the source root (CTest's WORKING_DIRECTORY), so "scenes/..." paths work.
 * The lighting tests' frame set-up (scene + G-buffer + uniforms) is in shading_fixtures.h. */
#ifndef SL_TESTUTIL_H
#define SL_TESTUTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "core/image.h"
#include "ibl/ibl.h"
#include "raster/raster.h"

/* A fresh temporary directory for this test process (removed by the OS's tmp cleaning). */
const char *test_tmpdir(void);
/* test_tmpdir()/name, in a static buffer rotated over 8 slots. */
const char *test_tmpfile(const char *name);
/* Write bytes to a file (asserts on failure). */
void test_write_bytes(const char *path, const void *bytes, size_t size);
/* Assert |a - b| <= tol, printing both values and the difference on failure. */
/* The sl_error `err` (a value) says `text` somewhere in its message; prints both when not. */
#define assert_msg_contains(err, text)                                                        \
    do {                                                                                      \
        if (!strstr((err).msg, (text))) {                                                     \
            print_error("error message \"%s\" does not contain \"%s\"\n", (err).msg, (text)); \
            fail();                                                                           \
        }                                                                                     \
    } while (0)

#define assert_near(a, b, tol) test_assert_near((double)(a), (double)(b), (double)(tol), #a, #b, __FILE__, __LINE__)
void test_assert_near(double a, double b, double tol, const char *sa, const char *sb, const char *file, int line);

/* Assert that two arrays of `count` texels of texel_size bytes (a multiple of 4) hold the same
 * bits. On failure it prints the printf-style description of what was compared, how many texels
 * differ, and the first one: x,y in rows of `width` texels (0: one row), its first differing
 * 32-bit word as a float and in hex. */
#define assert_same_texels(a, b, count, texel_size, width, ...) \
    test_assert_same_texels(__FILE__, __LINE__, a, b, count, texel_size, width, __VA_ARGS__)
void test_assert_same_texels(const char *file, int line, const void *a, const void *b, size_t count,
                             size_t texel_size, int width, const char *what, ...)
    __attribute__((format(printf, 8, 9)));

/* The same for two images: equal sizes and channel counts, then every pixel's bits. */
#define assert_same_image(a, b, ...) test_assert_same_image(__FILE__, __LINE__, a, b, __VA_ARGS__)
void test_assert_same_image(const char *file, int line, const sl_image *a, const sl_image *b, const char *what, ...)
    __attribute__((format(printf, 5, 6)));

/* The raster tests' rasterizer: `threads` threads (0: all cores), tiles of `tile` pixels, counters
 * when `stats`, the plain path when `plain`. Fails the test, printing sl_raster_create's message,
 * when it cannot be made. */
sl_raster *test_make_raster(int threads, int tile, bool stats, bool plain);

/* Rasterize scene into gb (resized to w x h) with a rasterizer made for desc and freed after;
 * asserts success and returns its counters (desc->stats must be set for them to count). */
sl_raster_stats test_raster_scene(const sl_raster_desc *desc, const sl_scene *scene, const sl_camera *cam, int w,
                                  int h, sl_gbuffer *gb);

/* Environments for the IBL tests: an sl_env whose w x h texels hold fn at their centre
 * directions (the specification's lat-long map, row 0 = v 0 = +Z), mip chain built. */
typedef double (*test_env_fn)(const double w[3], int channel);
void test_texel_centre_dir(int w, int h, int i, int j, double d[3]);
sl_env test_make_env(int w, int h, test_env_fn fn);

#endif
