/* test_image.c - src/core images and image I/O: allocation, repair, .hdr, .pfm, .png,
 * textures, atomic writes, whole-file reads and the timer.
 *
 * Expected values come from files built byte by byte in the tests (RGBE texels whose
 * decoding m * 2^(e - 136) is worked out by hand, big-endian floats written out as hex)
 * or from bounds stated in image.h (RGBE round trips within half a mantissa step). */
#include "testutil.h"

#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/image.h"
#include "core/timer.h"


/* ---- helpers ---- */

/* A small deterministic generator (numerical recipes LCG): tests must not depend on rand(). */
static unsigned lcg_state = 12345u;
static float lcg01(void)
{
    lcg_state = lcg_state * 1664525u + 1013904223u;
    return (float)(lcg_state >> 8) * (1.0f / 16777216.0f);
}

/* Append bytes to a growing test buffer. */
typedef struct {
    unsigned char data[8192];
    size_t size;
} buffer;
static void put(buffer *b, const void *bytes, size_t n)
{
    assert_true(b->size + n <= sizeof b->data);
    memcpy(b->data + b->size, bytes, n);
    b->size += n;
}
static void puts_(buffer *b, const char *s) { put(b, s, strlen(s)); }
static void put4(buffer *b, int a, int c, int d, int e)
{
    unsigned char p[4] = {(unsigned char)a, (unsigned char)c, (unsigned char)d, (unsigned char)e};
    put(b, p, 4);
}

static void random_image(sl_image *img, int w, int h, int channels, float lo_exp, float hi_exp)
{
    assert_true(sl_image_alloc(img, w, h, channels, NULL));
    size_t n = (size_t)w * (size_t)h * (size_t)channels;
    for (size_t i = 0; i < n; i++)
        img->data[i] = exp2f(lo_exp + (hi_exp - lo_exp) * lcg01()) * lcg01();
}

static bool file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* How many entries of `dir` are temporaries (".NAME.softlight-tmp.PID", or an older build's
 * "NAME.tmpXXXXXX"). */
static int count_temp_files(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += strstr(e->d_name, ".tmp") != NULL || strstr(e->d_name, ".softlight-tmp.") != NULL;
    closedir(d);
    return n;
}

static void read_all(const char *path, unsigned char **bytes, size_t *size)
{
    sl_error err = {0};
    if (!sl_read_file(path, (size_t)1 << 30, bytes, size, &err))
        print_error("%s\n", err.msg);
    assert_non_null(*bytes);
}

/* ---- sl_image ---- */

static void test_alloc(void **state)
{
    (void)state;
    sl_image img;
    sl_error err = {0};
    assert_true(sl_image_alloc(&img, 3, 2, 4, &err));
    assert_true(img.width == 3 && img.height == 2 && img.channels == 4);
    for (int i = 0; i < 24; i++)
        assert_true(img.data[i] == 0.0f);
    assert_true(sl_image_pixel(&img, 2, 1) == img.data + 20);
    sl_image_free(&img);
    assert_null(img.data);
    sl_image_free(&img); /* twice is harmless */

    assert_false(sl_image_alloc(&img, 0, 5, 3, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_false(sl_image_alloc(&img, 5, -1, 3, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_false(sl_image_alloc(&img, 5, 5, 2, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_null(img.data);
    /* 2^31 x 2^31 pixels would overflow any 64-bit byte count after * 16 */
    assert_false(sl_image_alloc(&img, 2147483647, 2147483647, 4, &err));
    assert_int_equal(err.code, SL_ERR_MEMORY);
    /* just over the cap: 65536 x 16385 x 1 floats = 4 GiB + 256 KiB */
    assert_false(sl_image_alloc(&img, 65536, 16385, 1, &err));
    assert_int_equal(err.code, SL_ERR_MEMORY);
}

static void test_flip_rows(void **state)
{
    (void)state;
    for (int h = 1; h <= 4; h++) { /* odd and even heights */
        sl_image img;
        assert_true(sl_image_alloc(&img, 2, h, 1, NULL));
        for (int y = 0; y < h; y++)
            for (int x = 0; x < 2; x++)
                sl_image_pixel(&img, x, y)[0] = (float)(10 * y + x);
        sl_image_flip_rows(&img);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < 2; x++)
                assert_true(sl_image_pixel(&img, x, y)[0] == (float)(10 * (h - 1 - y) + x));
        sl_image_free(&img);
    }
}

static void test_repair(void **state)
{
    (void)state;
    sl_image img;
    assert_true(sl_image_alloc(&img, 4, 2, 1, NULL));
    float v[8] = {NAN, INFINITY, -INFINITY, -0.5f, -0.0f, 0.5f, 3e38f, 1e-40f};
    memcpy(img.data, v, sizeof v);
    sl_image_repairs r;
    assert_int_equal(sl_image_repair(&img, &r), 4);
    assert_int_equal(r.nan_count, 1);
    assert_int_equal(r.inf_count, 2);
    assert_int_equal(r.negative_count, 1);
    float expect[8] = {0, 0, 0, 0, -0.0f, 0.5f, 3e38f, 1e-40f}; /* -0 is not negative; denormals stay */
    for (int i = 0; i < 8; i++)
        assert_true(img.data[i] == expect[i]);
    assert_int_equal(sl_image_repair(&img, NULL), 0);
    sl_image_free(&img);
}

/* ---- .hdr ---- */

static void hdr_header(buffer *b, const char *resolution)
{
    puts_(b, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n");
    puts_(b, resolution);
}

/* Flat scanlines built by hand: 3x2, texels chosen so m * 2^(e - 136) is easy to see. */
static void test_hdr_flat_by_hand(void **state)
{
    (void)state;
    buffer b = {0};
    hdr_header(&b, "-Y 2 +X 3\n");
    put4(&b, 128, 64, 0, 129);   /* 2^-7:  (1, 0.5, 0) */
    put4(&b, 0, 0, 0, 0);        /* e = 0: black */
    put4(&b, 255, 128, 2, 136);  /* 2^0:   (255, 128, 2) */
    put4(&b, 16, 32, 64, 140);   /* 2^4:   (256, 512, 1024) */
    put4(&b, 200, 100, 50, 0);   /* e = 0 is black whatever the mantissas */
    put4(&b, 192, 160, 255, 120); /* 2^-16 */
    sl_image img;
    sl_image_repairs rep;
    sl_error err = {0};
    if (!sl_image_parse_hdr(b.data, b.size, "flat.hdr", 0, &img, &rep, &err))
        print_error("%s\n", err.msg);
    assert_non_null(img.data);
    assert_true(img.width == 3 && img.height == 2 && img.channels == 3);
    float expect[18] = {1, 0.5f, 0, 0, 0, 0, 255, 128, 2, 256, 512, 1024, 0, 0, 0,
                        192.0f / 65536, 160.0f / 65536, 255.0f / 65536};
    for (int i = 0; i < 18; i++) {
        if (img.data[i] != expect[i])
            print_error("value %d: %.9g, expected %.9g\n", i, (double)img.data[i], (double)expect[i]);
        assert_true(img.data[i] == expect[i]);
    }
    assert_int_equal(rep.nan_count + rep.inf_count + rep.negative_count, 0);
    sl_image_free(&img);
}

/* One new-style RLE scanline built by hand: width 8, each component coded differently. */
static void test_hdr_rle_by_hand(void **state)
{
    (void)state;
    buffer b = {0};
    hdr_header(&b, "-Y 1 +X 8\n");
    put4(&b, 2, 2, 0, 8);
    unsigned char red[] = {128 + 8, 100};                                 /* one run of 8 */
    unsigned char green[] = {8, 1, 2, 3, 4, 5, 6, 7, 8};                  /* one literal of 8 */
    unsigned char blue[] = {128 + 3, 9, 5, 10, 11, 12, 13, 14};           /* run of 3, literal of 5 */
    unsigned char expo[] = {128 + 4, 136, 2, 137, 137, 128 + 2, 0};       /* run, literal, run */
    put(&b, red, sizeof red);
    put(&b, green, sizeof green);
    put(&b, blue, sizeof blue);
    put(&b, expo, sizeof expo);
    sl_image img;
    sl_error err = {0};
    if (!sl_image_parse_hdr(b.data, b.size, "rle.hdr", 0, &img, NULL, &err))
        print_error("%s\n", err.msg);
    assert_non_null(img.data);
    float bl[8] = {9, 9, 9, 10, 11, 12, 13, 14};
    float scale[8] = {1, 1, 1, 1, 2, 2, 0, 0}; /* exponents 136 x4, 137 x2, 0 x2 */
    for (int x = 0; x < 8; x++) {
        float *p = sl_image_pixel(&img, x, 0);
        assert_true(p[0] == 100.0f * scale[x]);
        assert_true(p[1] == (float)(x + 1) * scale[x]);
        assert_true(p[2] == bl[x] * scale[x]);
    }
    sl_image_free(&img);
}

/* Write random HDR values and read them back: each component within half a mantissa
 * step of the largest component, i.e. max / 255.5 < max / 255 (image.h). */
static void check_hdr_round_trip(int w, int h)
{
    sl_image img, back;
    random_image(&img, w, h, 3, -30.0f, 30.0f);
    img.data[0] = img.data[1] = img.data[2] = 0.0f; /* black must stay black */
    const char *path = test_tmpfile("round.hdr");
    sl_error err = {0};
    assert_true(sl_image_write_hdr(path, &img, &err));
    if (!sl_image_read_hdr(path, 0, &back, NULL, &err))
        print_error("%s\n", err.msg);
    assert_non_null(back.data);
    assert_true(back.width == w && back.height == h && back.channels == 3);
    double worst = 0.0;
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
        const float *a = img.data + 3 * i, *r = back.data + 3 * i;
        double m = fmax(a[0], fmax(a[1], a[2]));
        for (int c = 0; c < 3; c++) {
            double rel = m > 0 ? fabs((double)r[c] - (double)a[c]) / m : fabs((double)r[c]);
            worst = fmax(worst, rel);
        }
    }
    if (worst > 1.0 / 255.0)
        print_error("%dx%d: worst error %.6g of the largest component, bound %.6g\n", w, h, worst, 1.0 / 255.0);
    assert_true(worst <= 1.0 / 255.0);
    assert_true(back.data[0] == 0.0f && back.data[1] == 0.0f && back.data[2] == 0.0f);
    sl_image_free(&img);
    sl_image_free(&back);
}

static void test_hdr_round_trip(void **state)
{
    (void)state;
    check_hdr_round_trip(37, 5);    /* RLE scanlines */
    check_hdr_round_trip(5, 3);     /* narrower than 8: flat scanlines */
    check_hdr_round_trip(1, 1);
    check_hdr_round_trip(8, 2);     /* the narrowest RLE width */
    check_hdr_round_trip(300, 2);   /* literals longer than 128 */
}

/* The writer codes runs: a constant scanline of 100 texels is 4 + 4 * 2 bytes. */
static void test_hdr_writer_uses_rle(void **state)
{
    (void)state;
    sl_image img;
    assert_true(sl_image_alloc(&img, 100, 3, 3, NULL));
    for (size_t i = 0; i < 900; i++)
        img.data[i] = 0.75f;
    unsigned char *bytes;
    size_t size;
    assert_true(sl_image_encode_hdr(&img, &bytes, &size, NULL));
    const char *res = "-Y 3 +X 100\n";
    unsigned char *data = (unsigned char *)strstr((char *)bytes, res);
    assert_non_null(data);
    data += strlen(res);
    assert_int_equal(size - (size_t)(data - bytes), 3 * 12);
    assert_true(data[0] == 2 && data[1] == 2 && data[2] == 0 && data[3] == 100);
    assert_true(data[4] == 128 + 100); /* red: one run of 100 */
    /* 0.75 = 192 * 2^-8: mantissa 192, exponent byte 128 */
    assert_true(data[5] == 192 && data[11] == 128);
    /* values above the largest RGBE value are clamped, NaN and negatives written as 0 */
    img.data[0] = INFINITY;
    img.data[1] = NAN;
    img.data[2] = -1.0f;
    free(bytes);
    assert_true(sl_image_encode_hdr(&img, &bytes, &size, NULL));
    sl_image back;
    assert_true(sl_image_parse_hdr(bytes, size, "clamp.hdr", 0, &back, NULL, NULL));
    assert_true(back.data[0] == 255.0f * 0x1p119f && back.data[1] == 0.0f && back.data[2] == 0.0f);
    free(bytes);
    sl_image_free(&back);
    sl_image_free(&img);
}

static void test_hdr_studio(void **state)
{
    (void)state;
    const char *names[] = {"studio", "city", "forest", "interior", "sunset"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
        char path[128];
        snprintf(path, sizeof path, "scenes/envmaps/%s.hdr", names[k]);
        sl_image img;
        sl_image_repairs rep;
        sl_error err = {0};
        double t0 = sl_now_seconds();
        bool ok = sl_image_read_hdr(path, 0, &img, &rep, &err);
        double t1 = sl_now_seconds();
        if (!ok)
            print_error("%s\n", err.msg);
        assert_true(ok);
        assert_int_equal(img.width, 1024);
        assert_int_equal(img.height, 512);
        double maxv = 0.0;
        for (size_t i = 0; i < 1024 * 512 * 3; i++) {
            assert_true(isfinite(img.data[i]) && img.data[i] >= 0.0f);
            maxv = fmax(maxv, img.data[i]);
        }
        assert_true(maxv > 1.0); /* a real HDR environment */
        assert_int_equal(rep.nan_count + rep.inf_count + rep.negative_count, 0);
        printf("# %s.hdr: 1024x512 read in %.2f ms, brightest component %.6g\n", names[k], (t1 - t0) * 1e3, maxv);
        /* decoded texels are exactly m * 2^k, so writing and reading them again is lossless
         * (the writer's rounding has nothing to round) */
        unsigned char *bytes;
        size_t size;
        sl_image again;
        assert_true(sl_image_encode_hdr(&img, &bytes, &size, NULL));
        assert_true(sl_image_parse_hdr(bytes, size, "again.hdr", 0, &again, NULL, NULL));
        assert_memory_equal(img.data, again.data, sizeof(float) * 1024 * 512 * 3);
        free(bytes);
        sl_image_free(&again);
        sl_image_free(&img);
    }
}

/* Cut a file at `cut` bytes: the parse must fail, name the file, and (past the header)
 * name the offset where the data ends. */
static void check_truncated_hdr(const unsigned char *bytes, size_t cut, size_t header_end)
{
    sl_image img = {0};
    sl_error err = {0};
    bool ok = sl_image_parse_hdr(bytes, cut, "cut.hdr", 0, &img, NULL, &err);
    if (ok)
        print_error("a file cut at byte %zu parsed\n", cut);
    assert_false(ok);
    assert_null(img.data);
    assert_true(err.code == SL_ERR_FORMAT);
    assert_msg_contains(err, "cut.hdr: byte ");
    if (cut >= header_end) {
        char at[64];
        snprintf(at, sizeof at, "byte %zu: unexpected end of file", cut);
        assert_msg_contains(err, at);
    }
}

static void test_hdr_truncated(void **state)
{
    (void)state;
    /* a small RLE file and a small flat file, cut at every byte */
    int widths[] = {40, 5};
    for (int k = 0; k < 2; k++) {
        sl_image img;
        random_image(&img, widths[k], 6, 3, -4.0f, 4.0f);
        unsigned char *bytes;
        size_t size;
        assert_true(sl_image_encode_hdr(&img, &bytes, &size, NULL));
        size_t header_end = (size_t)(strstr((char *)bytes, "+X") - (char *)bytes);
        for (size_t cut = 0; cut < size; cut++)
            check_truncated_hdr(bytes, cut, header_end);
        free(bytes);
        sl_image_free(&img);
    }
    /* the shipped environment: its first 4000 bytes, then cuts every 49999 bytes */
    unsigned char *studio;
    size_t size;
    read_all("scenes/envmaps/studio.hdr", &studio, &size);
    check_truncated_hdr(studio, 4000, 40);
    for (size_t cut = 97; cut < size; cut += 49999)
        check_truncated_hdr(studio, cut, 40);
    free(studio);
}

static void check_hdr_rejected(const char *text, size_t len, sl_error_code code, const char *expect)
{
    sl_image img = {0};
    sl_error err = {0};
    assert_false(sl_image_parse_hdr((const unsigned char *)text, len, "bad.hdr", 0, &img, NULL, &err));
    assert_null(img.data);
    if (err.code != code)
        print_error("code %d, expected %d: %s\n", err.code, code, err.msg);
    assert_int_equal(err.code, code);
    assert_msg_contains(err, expect);
}
#define REJECT(text, code, expect) check_hdr_rejected(text, sizeof(text) - 1, code, expect)

static void test_hdr_rejects_bad_headers(void **state)
{
    (void)state;
    /* orientations other than -Y +X, named in the message */
    REJECT("#?RADIANCE\n\n+Y 1 +X 1\n\x80\x80\x80\x80", SL_ERR_UNSUPPORTED, "'+Y +X'");
    REJECT("#?RADIANCE\n\n-Y 1 -X 1\n\x80\x80\x80\x80", SL_ERR_UNSUPPORTED, "'-Y -X'");
    REJECT("#?RADIANCE\n\n-X 1 +Y 1\n\x80\x80\x80\x80", SL_ERR_UNSUPPORTED, "'-X +Y'");
    REJECT("#?RADIANCE\n\n-Y 1 +Y 1\n\x80\x80\x80\x80", SL_ERR_FORMAT, "byte 12: expected a resolution line");
    /* garbage and near misses */
    REJECT("P6\n1 1\n255\nabc", SL_ERR_FORMAT, "byte 0: not a Radiance .hdr file");
    REJECT("\x01\x02\x03\xff garbage", SL_ERR_FORMAT, "not a Radiance");
    REJECT("#?RADIANCEX\n\n-Y 1 +X 1\n", SL_ERR_FORMAT, "not a Radiance");
    REJECT("#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n", SL_ERR_UNSUPPORTED, "xyze");
    REJECT("#?RADIANCE\nFORMAT=jpeg\n\n-Y 1 +X 1\n", SL_ERR_FORMAT, "byte 11: unknown FORMAT 'jpeg'");
    REJECT("#?RGBE\n\n-Y 1 +X\n", SL_ERR_FORMAT, "expected a resolution line");
    REJECT("#?RGBE\n\n-Y one +X 1\n", SL_ERR_FORMAT, "expected a resolution line");
    REJECT("#?RGBE\n\n-Y 1 +X 1 \n", SL_ERR_FORMAT, "expected a resolution line");
    REJECT("#?RGBE\n\n-Y 0 +X 1\n", SL_ERR_FORMAT, "must be positive");
    REJECT("#?RGBE\n\n-Y 1 +X 1234567890\n", SL_ERR_FORMAT, "expected a resolution line");
    REJECT("#?RGBE\n\n-Y 40000 +X 1\n", SL_ERR_RANGE, "over the limits");
    REJECT("#?RGBE\n\n-Y 20000 +X 20000\n", SL_ERR_RANGE, "over the limits");
    /* 2^28 pixels claimed by a 40-byte file: refused before any allocation */
    REJECT("#?RGBE\n\n-Y 16384 +X 16384\n\x02\x02\x40\x00", SL_ERR_FORMAT, "need at least");
    /* pixel data errors */
    REJECT("#?RGBE\n\n-Y 1 +X 8\n\x02\x02\x00\x09\x88\x01\x88\x01\x88\x01\x88\x01", SL_ERR_FORMAT,
           "byte 18: scanline 0 declares width 9, the image is 8 wide");
    REJECT("#?RGBE\n\n-Y 1 +X 8\n\x02\x02\x00\x08\x8a\x01\x88\x01\x88\x01\x88\x01", SL_ERR_FORMAT,
           "byte 22: scanline 0 component 0: run of 10 at pixel 0 overflows width 8");
    REJECT("#?RGBE\n\n-Y 1 +X 8\n\x02\x02\x00\x08\x84\x01\x05\x01\x02\x03\x04\x05\x88\x01\x88\x01", SL_ERR_FORMAT,
           "literal of 5 at pixel 4 overflows width 8");
    REJECT("#?RGBE\n\n-Y 1 +X 8\n\x02\x02\x00\x08\x00\x01\x88\x01\x88\x01\x88\x01", SL_ERR_FORMAT,
           "literal of length 0");
    /* old-style runs are read (test_image_limits.c); one past the width is an error */
    REJECT("#?RGBE\n\n-Y 1 +X 2\n\x10\x10\x10\x80\x01\x01\x01\x05", SL_ERR_FORMAT,
           "byte 22: scanline 0: old-style run of 5 at pixel 1 overflows width 2");
    REJECT("", SL_ERR_FORMAT, "byte 0: unexpected end of file");
}

/* ---- .pfm ---- */

static void test_pfm_round_trip(void **state)
{
    (void)state;
    for (int channels = 1; channels <= 3; channels += 2) {
        sl_image img, back;
        random_image(&img, 7, 4, channels, -10.0f, 10.0f);
        img.data[3] = 0.0f;
        const char *path = test_tmpfile("round.pfm");
        sl_error err = {0};
        assert_true(sl_image_write_pfm(path, &img, &err));
        if (!sl_image_read_pfm(path, 0, &back, NULL, &err))
            print_error("%s\n", err.msg);
        assert_non_null(back.data);
        assert_true(back.width == 7 && back.height == 4 && back.channels == channels);
        assert_memory_equal(img.data, back.data, sizeof(float) * 28 * (size_t)channels); /* bit exact */
        sl_image_free(&img);
        sl_image_free(&back);
    }
}

/* Floats as big-endian hex, by hand: 1.0 = 3f800000, 2.0 = 40000000, 0.5 = 3f000000, 3.0 = 40400000. */
static void test_pfm_big_endian_and_row_order(void **state)
{
    (void)state;
    buffer b = {0};
    puts_(&b, "PF\n1 2\n1.0\n"); /* positive scale: big endian; 1 wide, 2 tall */
    put4(&b, 0x3f, 0x80, 0x00, 0x00); /* first stored row = BOTTOM row: (1, 2, 0.5) */
    put4(&b, 0x40, 0x00, 0x00, 0x00);
    put4(&b, 0x3f, 0x00, 0x00, 0x00);
    put4(&b, 0x40, 0x40, 0x00, 0x00); /* second stored row = top: (3, 0, 1) */
    put4(&b, 0x00, 0x00, 0x00, 0x00);
    put4(&b, 0x3f, 0x80, 0x00, 0x00);
    sl_image img;
    sl_error err = {0};
    if (!sl_image_parse_pfm(b.data, b.size, "be.pfm", 0, &img, NULL, &err))
        print_error("%s\n", err.msg);
    assert_non_null(img.data);
    assert_true(img.width == 1 && img.height == 2 && img.channels == 3);
    float expect[6] = {3, 0, 1, 1, 2, 0.5f}; /* row 0 = top */
    for (int i = 0; i < 6; i++)
        assert_true(img.data[i] == expect[i]);
    sl_image_free(&img);

    /* the same rows little endian, grey, in the shipped test file */
    assert_true(sl_image_read_pfm("tests/data/rows_le_1x2.pfm", 0, &img, NULL, &err));
    assert_true(img.width == 1 && img.height == 2 && img.channels == 1);
    assert_true(img.data[0] == 2.0f && img.data[1] == 1.0f); /* stored bottom (1) first, top (2) second */
    sl_image_free(&img);
    assert_true(sl_image_read_pfm("tests/data/rows_be_2x2.pfm", 0, &img, NULL, &err));
    assert_true(img.width == 2 && img.height == 2 && img.channels == 3);
    float expect2[12] = {3, 3, 3, 4, 4, 4, 1, 1, 1, 2, 2, 2};
    for (int i = 0; i < 12; i++)
        assert_true(img.data[i] == expect2[i]);
    sl_image_free(&img);
}

static void test_pfm_repair(void **state)
{
    (void)state;
    buffer b = {0};
    puts_(&b, "Pf\n5 1\n-1\n");
    float v[5] = {NAN, INFINITY, -INFINITY, -2.0f, 0.25f};
    for (int i = 0; i < 5; i++) { /* little endian, whatever the host */
        unsigned u;
        memcpy(&u, &v[i], 4);
        put4(&b, (int)(u & 0xff), (int)(u >> 8 & 0xff), (int)(u >> 16 & 0xff), (int)(u >> 24));
    }
    sl_image img;
    sl_image_repairs rep;
    assert_true(sl_image_parse_pfm(b.data, b.size, "nan.pfm", 0, &img, &rep, NULL));
    assert_int_equal(rep.nan_count, 1);
    assert_int_equal(rep.inf_count, 2);
    assert_int_equal(rep.negative_count, 1);
    for (int i = 0; i < 4; i++)
        assert_true(img.data[i] == 0.0f);
    assert_true(img.data[4] == 0.25f);
    sl_image_free(&img);
}

static void check_pfm_rejected(const char *text, size_t len, sl_error_code code, const char *expect)
{
    sl_image img = {0};
    sl_error err = {0};
    assert_false(sl_image_parse_pfm((const unsigned char *)text, len, "bad.pfm", 0, &img, NULL, &err));
    assert_null(img.data);
    if (err.code != code)
        print_error("code %d, expected %d: %s\n", err.code, code, err.msg);
    assert_int_equal(err.code, code);
    assert_msg_contains(err, expect);
}
#define REJECT_PFM(text, code, expect) check_pfm_rejected(text, sizeof(text) - 1, code, expect)

static void test_pfm_rejects(void **state)
{
    (void)state;
    REJECT_PFM("P6\n1 1\n255\n", SL_ERR_FORMAT, "byte 0: not a PFM file");
    REJECT_PFM("PF1 1 -1\n", SL_ERR_FORMAT, "byte 2: expected whitespace after 'PF'");
    REJECT_PFM("PF\n-1 1\n-1\n", SL_ERR_FORMAT, "byte 3: expected the width");
    REJECT_PFM("PF\n0 1\n-1\n", SL_ERR_FORMAT, "the width is 0");
    REJECT_PFM("PF\n1x 1\n-1\n", SL_ERR_FORMAT, "byte 4: expected whitespace after the width");
    REJECT_PFM("PF\n1234567890 1\n-1\n", SL_ERR_RANGE, "more than 9 digits");
    REJECT_PFM("PF\n40000 1\n-1\n", SL_ERR_RANGE, "over the limits");
    REJECT_PFM("PF\n1 1\n0.0\n", SL_ERR_FORMAT, "the scale is 0");
    REJECT_PFM("PF\n1 1\nabc\n", SL_ERR_FORMAT, "byte 7: expected the scale");
    REJECT_PFM("PF\n1 1\n-1.0e\n", SL_ERR_FORMAT, "expected the scale");
    REJECT_PFM("PF\n1 1\n-1.0", SL_ERR_FORMAT, "byte 11: unexpected end of file");
    REJECT_PFM("PF\n1 1\n-1\n\0\0\0\0\0\0\0\0\0\0\0\0\0", SL_ERR_FORMAT, "byte 22: 1 unexpected bytes");
    REJECT_PFM("Pf\n1 1\n-1\n\0\0\0", SL_ERR_FORMAT, "byte 13: unexpected end of file, expected 4 bytes");
    REJECT_PFM("", SL_ERR_FORMAT, "byte 0: unexpected end of file");
    REJECT_PFM("P", SL_ERR_FORMAT, "byte 1: unexpected end of file");

    /* a valid file cut at every byte fails, naming where it ends */
    sl_image img;
    random_image(&img, 3, 2, 3, 0.0f, 1.0f);
    unsigned char *bytes;
    size_t size;
    assert_true(sl_image_encode_pfm(&img, &bytes, &size, NULL));
    for (size_t cut = 0; cut < size; cut++) {
        sl_image out = {0};
        sl_error err = {0};
        assert_false(sl_image_parse_pfm(bytes, cut, "cut.pfm", 0, &out, NULL, &err));
        assert_null(out.data);
        char at[80];
        snprintf(at, sizeof at, "cut.pfm: byte %zu: unexpected end of file", cut);
        assert_msg_contains(err, at);
    }
    free(bytes);
    sl_image_free(&img);
}

/* ---- .png and textures ---- */

static void test_png_exact_bytes(void **state)
{
    (void)state;
    sl_image img;
    assert_true(sl_image_alloc(&img, 3, 2, 3, NULL));
    /* v * 255 rounded to nearest, clamped: 0.5 -> 127.5 -> 128, 0.2 -> 51, 0.998 -> 254.49 -> 254 */
    float v[18] = {0, 1, 0.5f, 0.2f, -1, 2, NAN, 0.998f, 1.0f / 255, 0.25f, 0.75f, 0.1f,
                   1, 1, 1, 0, 0, 0};
    unsigned char expect[18] = {0, 255, 128, 51, 0, 255, 0, 254, 1, 64, 191, 26, 255, 255, 255, 0, 0, 0};
    memcpy(img.data, v, sizeof v);
    const char *path = test_tmpfile("known.png");
    sl_error err = {0};
    assert_true(sl_image_write_png(path, &img, &err));
    unsigned char *file;
    size_t size;
    read_all(path, &file, &size);
    sl_raw_image raw;
    assert_true(sl_image_parse_raw(file, size, "known.png", 0, NULL, &raw, &err));
    assert_true(raw.width == 3 && raw.height == 2 && raw.channels == 3 && raw.bits == 8);
    assert_memory_equal(raw.pixels, expect, 18);
    sl_raw_image_free(&raw);
    free(file);
    sl_image_free(&img);

    /* one channel stays one channel */
    assert_true(sl_image_alloc(&img, 2, 1, 1, NULL));
    img.data[0] = 0.5f;
    img.data[1] = 1.0f;
    unsigned char *bytes;
    assert_true(sl_image_encode_png(&img, &bytes, &size, NULL));
    assert_true(sl_image_parse_raw(bytes, size, "grey.png", 0, NULL, &raw, &err));
    const unsigned char *px = raw.pixels;
    assert_true(raw.width == 2 && raw.height == 1 && raw.channels == 1 && px[0] == 128 && px[1] == 255);
    sl_raw_image_free(&raw);
    free(bytes);
    sl_image_free(&img);

    assert_true(sl_image_alloc(&img, 2, 1, 4, NULL));
    assert_false(sl_image_encode_png(&img, &bytes, &size, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    sl_image_free(&img);
}

static void test_texture_srgb(void **state)
{
    (void)state;
    /* codes 0, 255, 128, 10 (linear segment), 64 and 200 through a PNG file */
    sl_image img;
    assert_true(sl_image_alloc(&img, 3, 2, 3, NULL));
    int codes[6] = {0, 255, 128, 10, 64, 200};
    for (int i = 0; i < 6; i++)
        for (int c = 0; c < 3; c++)
            img.data[3 * i + c] = (float)codes[i] / 255.0f;
    const char *path = test_tmpfile("texture.png");
    assert_true(sl_image_write_png(path, &img, NULL));
    sl_image_free(&img);
    sl_error err = {0};
    if (!sl_image_read_texture(path, 0, &img, &err))
        print_error("%s\n", err.msg);
    assert_non_null(img.data);
    assert_true(img.width == 3 && img.height == 2 && img.channels == 3);
    /* IEC 61966-2-1 by hand: 10/255/12.92; ((c + 0.055)/1.055)^2.4 above 0.04045 */
    double expect[6] = {0.0, 1.0, 0.2158605, 0.00303527, 0.05126946, 0.57758044};
    for (int i = 0; i < 6; i++)
        for (int c = 0; c < 3; c++)
            assert_near(img.data[3 * i + c], expect[i], 1e-7);
    sl_image_free(&img);
    assert_near(sl_srgb8_to_linear(128), 0.2158605, 1e-7);
    assert_true(sl_srgb8_to_linear(0) == 0.0f && sl_srgb8_to_linear(255) == 1.0f);

    /* a grey PNG becomes three equal channels */
    assert_true(sl_image_alloc(&img, 1, 1, 1, NULL));
    img.data[0] = 128.0f / 255.0f;
    assert_true(sl_image_write_png(path, &img, NULL));
    sl_image_free(&img);
    assert_true(sl_image_read_texture(path, 0, &img, NULL));
    assert_true(img.channels == 3);
    for (int c = 0; c < 3; c++)
        assert_near(img.data[c], 0.2158605, 1e-7);
    sl_image_free(&img);

    /* not an image; a truncated PNG */
    const char *bad = test_tmpfile("bad.png");
    test_write_bytes(bad, "hello", 5);
    assert_false(sl_image_read_texture(bad, 0, &img, &err));
    assert_int_equal(err.code, SL_ERR_FORMAT);
    assert_msg_contains(err, "bad.png");
    assert_null(img.data);
    assert_false(sl_image_read_texture(test_tmpfile("missing.png"), 0, &img, &err));
    assert_int_equal(err.code, SL_ERR_IO);
}

/* ---- files ---- */

static void test_read_file(void **state)
{
    (void)state;
    const char *path = test_tmpfile("hundred.bin");
    unsigned char data[100];
    for (int i = 0; i < 100; i++)
        data[i] = (unsigned char)i;
    test_write_bytes(path, data, 100);
    unsigned char *bytes;
    size_t size;
    sl_error err = {0};
    assert_true(sl_read_file(path, 100, &bytes, &size, &err));
    assert_int_equal(size, 100);
    assert_memory_equal(bytes, data, 100);
    free(bytes);
    assert_false(sl_read_file(path, 99, &bytes, &size, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_null(bytes);
    const char *empty = test_tmpfile("empty.bin");
    test_write_bytes(empty, "", 0);
    assert_true(sl_read_file(empty, 10, &bytes, &size, &err));
    assert_int_equal(size, 0);
    free(bytes);
    assert_false(sl_read_file(test_tmpfile("none.bin"), 10, &bytes, &size, &err));
    assert_int_equal(err.code, SL_ERR_IO);
    assert_msg_contains(err, "none.bin: cannot open");
    assert_false(sl_read_file(test_tmpdir(), 10, &bytes, &size, &err));
    assert_int_equal(err.code, SL_ERR_IO);
    /* an endless stream stops at the cap */
    assert_false(sl_read_file("/dev/zero", 100000, &bytes, &size, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
}

static void test_atomic_write(void **state)
{
    (void)state;
    /* into a directory that does not exist: fails, creates nothing */
    char missing_dir[512], target[600];
    snprintf(missing_dir, sizeof missing_dir, "%s/no-such-dir", test_tmpdir());
    snprintf(target, sizeof target, "%s/out.png", missing_dir);
    sl_image img;
    assert_true(sl_image_alloc(&img, 2, 2, 3, NULL));
    sl_error err = {0};
    assert_false(sl_image_write_png(target, &img, &err));
    assert_int_equal(err.code, SL_ERR_IO);
    assert_msg_contains(err, "no-such-dir/out.png");
    assert_false(file_exists(missing_dir));

    /* a fresh directory to count stray files in */
    char dir[512], path[600];
    snprintf(dir, sizeof dir, "%s/atomic", test_tmpdir());
    assert_int_equal(mkdir(dir, 0755), 0);
    snprintf(path, sizeof path, "%s/image.hdr", dir);
    test_write_bytes(path, "old contents", 12);
    assert_int_equal(chmod(path, 0640), 0);

    /* an invalid image (1 channel for .hdr) over an existing file: old file intact */
    sl_image grey;
    assert_true(sl_image_alloc(&grey, 2, 2, 1, NULL));
    assert_false(sl_image_write_hdr(path, &grey, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_msg_contains(err, "image.hdr: hdr writer: needs 3 channels");
    sl_image_free(&grey);
    unsigned char *bytes;
    size_t size;
    read_all(path, &bytes, &size);
    assert_true(size == 12 && !memcmp(bytes, "old contents", 12));
    free(bytes);

    /* a write that fails midway (file size limit hit after some bytes): old file intact, no temp file */
    struct rlimit old_limit, small;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
    small = old_limit;
    small.rlim_cur = 1000;
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
    static unsigned char big[20000];
    bool ok = sl_write_file_atomic(path, big, sizeof big, &err);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &old_limit), 0);
    signal(SIGXFSZ, old_handler);
    assert_false(ok);
    assert_int_equal(err.code, SL_ERR_IO);
    assert_msg_contains(err, "write failed after 1000 of 20000 bytes");
    read_all(path, &bytes, &size);
    assert_true(size == 12 && !memcmp(bytes, "old contents", 12));
    free(bytes);
    assert_int_equal(count_temp_files(dir), 0);

    /* a good write replaces the file, keeps its permissions, leaves no temp file */
    assert_true(sl_image_write_hdr(path, &img, &err));
    sl_image back;
    assert_true(sl_image_read_hdr(path, 0, &back, NULL, &err));
    assert_true(back.width == 2 && back.height == 2);
    sl_image_free(&back);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0640);
    assert_int_equal(count_temp_files(dir), 0);
    /* a new file gets 0666 minus the umask, not mkstemp's 0600 */
    char fresh[600];
    snprintf(fresh, sizeof fresh, "%s/fresh.pfm", dir);
    mode_t mask = umask(022);
    assert_true(sl_image_write_pfm(fresh, &img, &err));
    umask(mask);
    assert_int_equal(stat(fresh, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0644);
    /* the target is a directory: rename fails, the temp file is removed */
    assert_false(sl_write_file_atomic(dir, "x", 1, &err));
    assert_int_equal(err.code, SL_ERR_IO);
    assert_int_equal(count_temp_files(test_tmpdir()), 0);
    sl_image_free(&img);
}

static void test_timer(void **state)
{
    (void)state;
    double t0 = sl_now_seconds();
    struct timespec ten_ms = {0, 10000000};
    nanosleep(&ten_ms, NULL);
    double t1 = sl_now_seconds();
    assert_true(t0 > 0.0);
    assert_true(t1 - t0 >= 0.0099);
    assert_true(t1 - t0 < 5.0);
    for (int i = 0; i < 1000; i++) { /* never runs backwards */
        double t = sl_now_seconds();
        assert_true(t >= t1);
        t1 = t;
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_alloc),
        cmocka_unit_test(test_flip_rows),
        cmocka_unit_test(test_repair),
        cmocka_unit_test(test_hdr_flat_by_hand),
        cmocka_unit_test(test_hdr_rle_by_hand),
        cmocka_unit_test(test_hdr_round_trip),
        cmocka_unit_test(test_hdr_writer_uses_rle),
        cmocka_unit_test(test_hdr_studio),
        cmocka_unit_test(test_hdr_truncated),
        cmocka_unit_test(test_hdr_rejects_bad_headers),
        cmocka_unit_test(test_pfm_round_trip),
        cmocka_unit_test(test_pfm_big_endian_and_row_order),
        cmocka_unit_test(test_pfm_repair),
        cmocka_unit_test(test_pfm_rejects),
        cmocka_unit_test(test_png_exact_bytes),
        cmocka_unit_test(test_texture_srgb),
        cmocka_unit_test(test_read_file),
        cmocka_unit_test(test_atomic_write),
        cmocka_unit_test(test_timer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
