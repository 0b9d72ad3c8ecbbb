/* testutil.c - see testutil.h. */
#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <unistd.h>

const char *test_tmpdir(void)
{
    static char dir[256];
    if (!dir[0]) {
        const char *base = getenv("TMPDIR");
        snprintf(dir, sizeof dir, "%s/softlight-test-XXXXXX", base && base[0] ? base : "/tmp");
        if (!mkdtemp(dir)) {
            fprintf(stderr, "cannot create a temporary directory\n");
            fail();
        }
    }
    return dir;
}

const char *test_tmpfile(const char *name)
{
    static char slots[8][512];
    static int next;
    char *p = slots[next++ & 7];
    snprintf(p, 512, "%s/%s", test_tmpdir(), name);
    return p;
}

void test_write_bytes(const char *path, const void *bytes, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(bytes, 1, size, f), size);
    assert_int_equal(fclose(f), 0);
}

void test_assert_near(double a, double b, double tol, const char *sa, const char *sb, const char *file, int line)
{
    double d = a - b;
    if (!(d <= tol && -d <= tol)) {
        print_error("%s:%d: %s = %.9g and %s = %.9g differ by %.3g (tolerance %.3g)\n", file, line, sa, a, sb,
                    b, d, tol);
        _fail(file, line);
    }
}

/* Fail at file:line if a and b differ, naming the first differing texel (x,y in rows of width)
 * and its first differing 32-bit word as a float and in hex. texel_size is a multiple of 4. */
static void report_difference(const char *file, int line, const unsigned char *a, const unsigned char *b,
                              size_t count, size_t texel_size, int width, const char *what, va_list ap)
{
    size_t first = count, differing = 0;
    for (size_t i = 0; i < count; i++)
        if (memcmp(a + i * texel_size, b + i * texel_size, texel_size) != 0 && differing++ == 0)
            first = i;
    if (!differing)
        return;
    const unsigned char *pa = a + first * texel_size, *pb = b + first * texel_size;
    size_t word = 0;
    while (4 * word + 4 < texel_size && !memcmp(pa + 4 * word, pb + 4 * word, 4))
        word++;
    uint32_t ua, ub;
    float fa, fb;
    memcpy(&ua, pa + 4 * word, 4);
    memcpy(&ub, pb + 4 * word, 4);
    memcpy(&fa, &ua, 4);
    memcpy(&fb, &ub, 4);
    char label[256];
    vsnprintf(label, sizeof label, what, ap);
    size_t w = width > 0 ? (size_t)width : count;
    print_error("%s:%d: %s: %zu of %zu texels differ; the first at %zu,%zu, word %zu: %.9g (0x%08x) against "
                "%.9g (0x%08x)\n",
                file, line, label, differing, count, first % w, first / w, word, (double)fa, ua, (double)fb, ub);
    _fail(file, line);
}

void test_assert_same_texels(const char *file, int line, const void *a, const void *b, size_t count,
                             size_t texel_size, int width, const char *what, ...)
{
    va_list ap;
    va_start(ap, what);
    report_difference(file, line, a, b, count, texel_size, width, what, ap);
    va_end(ap);
}

void test_assert_same_image(const char *file, int line, const sl_image *a, const sl_image *b, const char *what, ...)
{
    va_list ap;
    va_start(ap, what);
    if (a->width != b->width || a->height != b->height || a->channels != b->channels) {
        char label[256];
        vsnprintf(label, sizeof label, what, ap);
        print_error("%s:%d: %s: images of %dx%dx%d and %dx%dx%d\n", file, line, label, a->width, a->height,
                    a->channels, b->width, b->height, b->channels);
        _fail(file, line);
    }
    report_difference(file, line, (const unsigned char *)a->data, (const unsigned char *)b->data,
                      (size_t)a->width * (size_t)a->height, (size_t)a->channels * sizeof(float), a->width, what, ap);
    va_end(ap);
}

sl_raster_stats test_raster_scene(const sl_raster_desc *desc, const sl_scene *scene, const sl_camera *cam, int w,
                                  int h, sl_gbuffer *gb)
{
    sl_error err = {0};
    sl_raster *r = sl_raster_create(desc, &err);
    if (!r)
        fail_msg("sl_raster_create: %s", err.msg);
    if (!sl_gbuffer_resize(gb, w, h, &err) || !sl_raster_scene(r, scene, cam, gb, &err))
        fail_msg("threads %d, tile %d: %s", desc->threads, desc->tile_size, err.msg);
    sl_raster_stats st = sl_raster_get_stats(r);
    sl_raster_destroy(r);
    return st;
}

void test_texel_centre_dir(int w, int h, int i, int j, double d[3])
{
    const double pi = 3.14159265358979323846;
    double phi = 2.0 * pi * (0.5 - (i + 0.5) / w), theta = pi * (j + 0.5) / h;
    d[0] = cos(phi) * sin(theta);
    d[1] = sin(phi) * sin(theta);
    d[2] = cos(theta);
}

sl_env test_make_env(int w, int h, test_env_fn fn)
{
    sl_image img;
    sl_error err = {0};
    assert_true(sl_image_alloc(&img, w, h, 3, &err));
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            double d[3];
            test_texel_centre_dir(w, h, i, j, d);
            float *p = sl_image_pixel(&img, i, j);
            for (int c = 0; c < 3; c++)
                p[c] = (float)fn(d, c);
        }
    sl_env env;
    assert_true(sl_env_build(&env, &img, 0, &err));
    sl_image_free(&img);
    return env;
}

sl_raster *test_make_raster(int threads, int tile, bool stats, bool plain)
{
    sl_error err = {0};
    sl_raster *r = sl_raster_create(
        &(sl_raster_desc){.threads = threads, .tile_size = tile, .stats = stats, .plain = plain}, &err);
    if (!r)
        print_error("sl_raster_create: %s\n", err.msg);
    assert_non_null(r);
    return r;
}
