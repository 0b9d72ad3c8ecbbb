/* test_image_limits.c - what the image readers do with hostile and unusual files: the
 * image memory budget checked against a declared size before allocating,
 * the magic read before the rest of a file, the .hdr header without its blank line, old-style
 * run-length scanlines, and CRLF header lines.
 *
 * Every "bomb" here is a few kilobytes declaring a large image: the tests pass when the reader
 * refuses it without allocating it, so they stay fast and small in memory. */
#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/image.h"

/* A growing byte buffer. */
typedef struct {
    unsigned char *data;
    size_t size, cap;
} bytes_buf;

static void put(bytes_buf *b, const void *p, size_t n)
{
    if (b->size + n > b->cap) {
        b->cap = (b->size + n) * 2;
        b->data = realloc(b->data, b->cap);
        assert_non_null(b->data);
    }
    memcpy(b->data + b->size, p, n);
    b->size += n;
}
static void put_str(bytes_buf *b, const char *s) { put(b, s, strlen(s)); }
static void put4(bytes_buf *b, int r, int g, int bl, int e)
{
    unsigned char p[4] = {(unsigned char)r, (unsigned char)g, (unsigned char)bl, (unsigned char)e};
    put(b, p, 4);
}

/* m * 2^(e - 136), the reader's decoding */
static float rgbe(int m, int e) { return e ? (float)m * ldexpf(1.0f, e - 136) : 0.0f; }

/* An old-style RLE file of width x height where each scanline is one pixel and the runs that
 * repeat it to the end of the line: (1,1,1,n) with n << 0, << 8, << 16 ... */
static bytes_buf old_rle_file(int width, int height)
{
    bytes_buf b = {0};
    char head[96];
    snprintf(head, sizeof head, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n", height, width);
    put_str(&b, head);
    for (int y = 0; y < height; y++) {
        put4(&b, 100 + y % 100, 50, 25, 130);
        for (unsigned left = (unsigned)width - 1, shift = 0; left > 0; left >>= 8, shift += 8)
            put4(&b, 1, 1, 1, (int)(left & 255));
    }
    return b;
}

/* ---- the memory budget ---- */

static void test_hdr_budget_refuses_before_allocating(void **state)
{
    (void)state;
    /* 16384 x 8192 (1.5 GiB of floats) in 96 KiB of old-style runs: refused under the default
     * budget, before the image is allocated (this test runs under the sanitizers' and CI's
     * memory limits, so an allocation of that size would show) */
    bytes_buf b = old_rle_file(16384, 8192);
    sl_image img;
    sl_error err = {0};
    assert_false(sl_image_parse_hdr(b.data, b.size, "bomb.hdr", 0, &img, NULL, &err));
    assert_null(img.data);
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_msg_contains(err, "bomb.hdr: byte 35: image 16384x8192 needs 1536 MiB");
    assert_msg_contains(err, "image memory budget of 1024 MiB (raise it with --image-memory 1536)");
    free(b.data);

    /* a budget a user gives: 64x64 RGB is 48 KiB; 1 MiB reads it, and a 1024 x 512 one
     * (6 MiB) is refused */
    b = old_rle_file(64, 64);
    assert_true(sl_image_parse_hdr(b.data, b.size, "small.hdr", (size_t)1 << 20, &img, NULL, &err));
    sl_image_free(&img);
    free(b.data);
    b = old_rle_file(1024, 512);
    assert_false(sl_image_parse_hdr(b.data, b.size, "big.hdr", (size_t)1 << 20, &img, NULL, &err));
    assert_msg_contains(err, "needs 6 MiB in memory, more than the image memory budget of 1 MiB");
    assert_true(sl_image_parse_hdr(b.data, b.size, "big.hdr", (size_t)6 << 20, &img, NULL, &err));
    sl_image_free(&img);
    free(b.data);
}

static void test_pfm_and_png_budget(void **state)
{
    (void)state;
    /* PFM 512 x 512 RGB: 3 MiB */
    sl_image img;
    sl_error err = {0};
    assert_true(sl_image_alloc(&img, 512, 512, 3, &err));
    const char *pfm = test_tmpfile("budget.pfm"), *png = test_tmpfile("budget.png");
    assert_true(sl_image_write_pfm(pfm, &img, &err));
    assert_true(sl_image_write_png(png, &img, &err));
    sl_image_free(&img);
    assert_false(sl_image_read_pfm(pfm, (size_t)5 << 19, &img, NULL, &err)); /* 2.5 MiB */
    assert_null(img.data);
    assert_msg_contains(err, "budget.pfm: byte 3: image 512x512 needs 3 MiB in memory");
    assert_msg_contains(err, "--image-memory 3");
    assert_true(sl_image_read_pfm(pfm, (size_t)3 << 20, &img, NULL, &err));
    sl_image_free(&img);
    /* a PFM larger than the budget is not read at all */
    assert_false(sl_image_read_pfm(pfm, (size_t)1 << 20, &img, NULL, &err));
    assert_msg_contains(err, "more than the 2097152 allowed by the image memory budget (raise it with --image-memory)");
    /* PNG: the float image and the decoder's share (three 8-bit RGB images), 512 x 512 x (12 + 9) bytes */
    assert_false(sl_image_read_texture(png, (size_t)4 << 20, &img, &err));
    assert_msg_contains(err, "budget.png: byte 16: image 512x512 needs 6 MiB in memory");
    assert_true(sl_image_read_texture(png, (size_t)6 << 20, &img, &err));
    sl_image_free(&img);
}

/* A PNG whose compressed data inflates far past its 1 x 1 image (a zlib bomb): the decoder
 * inflates only what the image's rows hold, so it reads the 1 x 1 image within a 1 MiB budget
 * and never the 16 MiB beyond. */
static void test_png_zlib_bomb(void **state)
{
    (void)state;
    /* Easiest honest bomb: a valid 4096 x 4096 grey PNG (zeros compress ~1000:1) whose IHDR then
     * claims 1 x 1: 16 MiB of compressed rows for an image of 2 bytes. */
    sl_image img;
    sl_error err = {0};
    assert_true(sl_image_alloc(&img, 4096, 4096, 1, &err));
    unsigned char *bytes;
    size_t size;
    assert_true(sl_image_encode_png(&img, &bytes, &size, &err));
    sl_image_free(&img);
    assert_true(size < ((size_t)1 << 20));
    /* IHDR data at 16: width, height (big endian); fix its CRC at 29 */
    unsigned char one[8] = {0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(bytes + 16, one, 8);
    unsigned long crc = 0xffffffffUL;
    for (size_t i = 12; i < 29; i++) {
        crc ^= bytes[i];
        for (int k = 0; k < 8; k++)
            crc = (crc >> 1) ^ (0xedb88320UL & (0UL - (crc & 1)));
    }
    crc ^= 0xffffffffUL;
    for (int k = 0; k < 4; k++)
        bytes[29 + k] = (unsigned char)(crc >> (24 - 8 * k));
    const char *path = test_tmpfile("zbomb.png");
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(bytes, 1, size, f), size);
    fclose(f);
    free(bytes);
    if (!sl_image_read_texture(path, (size_t)1 << 20, &img, &err))
        print_error("%s\n", err.msg);
    assert_true(img.width == 1 && img.height == 1 && img.data[0] == 0.0f);
    sl_image_free(&img);
}

/* ---- the magic before the whole file ---- */

static void test_magic_before_whole_file(void **state)
{
    (void)state;
    /* /dev/zero is endless: each reader must fail on its first bytes, not read 2 GiB first */
    sl_image img;
    sl_error err = {0};
    assert_false(sl_image_read_hdr("/dev/zero", 0, &img, NULL, &err));
    assert_msg_contains(err, "/dev/zero: byte 0: not a Radiance .hdr file");
    assert_false(sl_image_read_pfm("/dev/zero", 0, &img, NULL, &err));
    assert_msg_contains(err, "/dev/zero: byte 0: not a PFM file");
    assert_false(sl_image_read_texture("/dev/zero", 0, &img, &err));
    assert_msg_contains(err, "/dev/zero: byte 0: not a PNG, JPEG, BMP or TGA file");
    /* a file shorter than the magic: the parser's own message */
    const char *tiny = test_tmpfile("tiny.hdr");
    FILE *f = fopen(tiny, "wb");
    assert_non_null(f);
    fputs("#?RAD", f);
    fclose(f);
    assert_false(sl_image_read_hdr(tiny, 0, &img, NULL, &err));
    assert_msg_contains(err, "tiny.hdr: byte 5: unexpected end of file");
}

/* ---- .hdr messages and formats ---- */

static void test_hdr_missing_blank_line(void **state)
{
    (void)state;
    /* the bomb without its blank line: the resolution line is where the header went
     * wrong (byte 34), not the pixel data far beyond */
    bytes_buf b = {0};
    put_str(&b, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n-Y 2 +X 8\n");
    for (int y = 0; y < 2; y++) {
        put4(&b, 2, 2, 0, 8);
        for (int c = 0; c < 4; c++)
            put(&b, "\x88\x0a", 2); /* a run whose value is '\n' */
    }
    sl_image img;
    sl_error err = {0};
    assert_false(sl_image_parse_hdr(b.data, b.size, "noblank.hdr", 0, &img, NULL, &err));
    assert_int_equal(err.code, SL_ERR_FORMAT);
    assert_msg_contains(err, "noblank.hdr: byte 34: found the resolution line '-Y 2 +X 8' in the header");
    free(b.data);
    /* binary data where a header line should be */
    static const char bin[] = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\x02\x02\x00\x08\x88\n";
    assert_false(sl_image_parse_hdr((const unsigned char *)bin, sizeof bin - 1, "bin.hdr", 0, &img, NULL, &err));
    assert_msg_contains(err, "bin.hdr: byte 34: binary data (byte 0x02) in the header line starting at byte 34");
}

static void test_hdr_old_rle(void **state)
{
    (void)state;
    /* width 300: A, run of 4 (A x5), B, runs 38 and 1 << 8 (B and 294 repeats): 300 pixels;
     * second line: a new-style scanline (a file may mix them, as Radiance writes and reads) */
    bytes_buf b = {0};
    put_str(&b, "#?RADIANCE\n\n-Y 2 +X 300\n");
    put4(&b, 128, 64, 32, 129);
    put4(&b, 1, 1, 1, 4);
    put4(&b, 200, 0, 100, 140);
    put4(&b, 1, 1, 1, 38);
    put4(&b, 1, 1, 1, 1);
    put4(&b, 2, 2, 300 >> 8, 300 & 255);
    unsigned char runs[] = {0xff, 7, 0xff, 7, 0xae, 7}; /* 127 + 127 + 46 = 300 */
    for (int c = 0; c < 4; c++)
        put(&b, runs, sizeof runs);
    sl_image img;
    sl_error err = {0};
    if (!sl_image_parse_hdr(b.data, b.size, "old.hdr", 0, &img, NULL, &err)) {
        print_error("%s\n", err.msg);
        fail();
    }
    assert_int_equal(img.width, 300);
    for (int x = 0; x < 300; x++) {
        const float *p = sl_image_pixel(&img, x, 0);
        bool a = x < 5;
        assert_true(p[0] == (a ? rgbe(128, 129) : rgbe(200, 140)));
        assert_true(p[1] == (a ? rgbe(64, 129) : 0.0f));
        assert_true(p[2] == (a ? rgbe(32, 129) : rgbe(100, 140)));
        assert_true(sl_image_pixel(&img, x, 1)[0] == rgbe(7, 7));
    }
    sl_image_free(&img);
    free(b.data);
    /* the shift grows only over consecutive runs: A, run 2, B, run 2 -> A A A B B B */
    static const char reset[] = "#?RADIANCE\n\n-Y 1 +X 6\n"
                                "\x80\x80\x80\x81" "\x01\x01\x01\x02" "\x40\x40\x40\x81" "\x01\x01\x01\x02";
    assert_true(sl_image_parse_hdr((const unsigned char *)reset, sizeof reset - 1, "reset.hdr", 0, &img, NULL, &err));
    assert_true(sl_image_pixel(&img, 2, 0)[0] == rgbe(128, 129) && sl_image_pixel(&img, 3, 0)[0] == rgbe(64, 129));
    assert_true(sl_image_pixel(&img, 5, 0)[0] == rgbe(64, 129));
    sl_image_free(&img);
    /* a big old-style file round trips through the writer */
    b = old_rle_file(5000, 3);
    assert_true(sl_image_parse_hdr(b.data, b.size, "wide.hdr", 0, &img, NULL, &err));
    assert_true(sl_image_pixel(&img, 4999, 2)[0] == rgbe(102, 130));
    sl_image_free(&img);
    free(b.data);
    /* errors: a run with nothing before it, a run past the width */
    static const char first[] = "#?RADIANCE\n\n-Y 1 +X 2\n\x01\x01\x01\x02\x10\x10\x10\x80";
    assert_false(sl_image_parse_hdr((const unsigned char *)first, sizeof first - 1, "first.hdr", 0, &img, NULL, &err));
    assert_msg_contains(err, "first.hdr: byte 22: scanline 0 starts with an old-style run (1,1,1,2)");
    static const char over[] = "#?RADIANCE\n\n-Y 1 +X 2\n\x10\x10\x10\x80\x01\x01\x01\x05";
    assert_false(sl_image_parse_hdr((const unsigned char *)over, sizeof over - 1, "over.hdr", 0, &img, NULL, &err));
    assert_msg_contains(err, "over.hdr: byte 26: scanline 0: old-style run of 5 at pixel 1 overflows width 2");
    /* five runs in a row: the fifth would be n << 32 */
    static const char shift[] = "#?RADIANCE\n\n-Y 1 +X 2\n\x10\x10\x10\x80\x01\x01\x01\x00\x01\x01\x01\x00"
                                "\x01\x01\x01\x00\x01\x01\x01\x00\x01\x01\x01\x01";
    assert_false(sl_image_parse_hdr((const unsigned char *)shift, sizeof shift - 1, "shift.hdr", 0, &img, NULL, &err));
    assert_msg_contains(err, "overflows width 2");
}

/* The file the writer makes for `img`, with every header line (the first four) ending in CRLF. */
static bytes_buf crlf_copy(const unsigned char *bytes, size_t size)
{
    bytes_buf b = {0};
    int lines = 0;
    size_t i = 0;
    for (; i < size && lines < 5; i++) {
        if (bytes[i] == '\n') {
            put(&b, "\r", 1);
            lines++;
        }
        put(&b, bytes + i, 1);
    }
    put(&b, bytes + i, size - i);
    return b;
}

static void test_hdr_crlf_header(void **state)
{
    (void)state;
    sl_image img, back;
    sl_error err = {0};
    assert_true(sl_image_alloc(&img, 40, 3, 3, &err));
    for (size_t i = 0; i < 40 * 3 * 3; i++)
        img.data[i] = (float)(i % 17) * 0.25f;
    unsigned char *bytes;
    size_t size;
    assert_true(sl_image_encode_hdr(&img, &bytes, &size, &err));
    bytes_buf b = crlf_copy(bytes, size);
    assert_int_equal(b.size, size + 5); /* magic, FORMAT, SOFTWARE, blank, resolution */
    if (!sl_image_parse_hdr(b.data, b.size, "crlf.hdr", 0, &back, NULL, &err)) {
        print_error("%s\n", err.msg);
        fail();
    }
    sl_image lf;
    assert_true(sl_image_parse_hdr(bytes, size, "lf.hdr", 0, &lf, NULL, &err));
    assert_memory_equal(back.data, lf.data, 40 * 3 * 3 * sizeof(float));
    sl_image_free(&back);
    sl_image_free(&lf);
    /* converted as text: a byte more in the pixels (0x0A -> 0x0D 0x0A); named as CRLF */
    put(&b, "\r", 1);
    assert_false(sl_image_parse_hdr(b.data, b.size, "crlf.hdr", 0, &back, NULL, &err));
    assert_msg_contains(err, "1 bytes after the pixel data (the header's lines end in CRLF");
    free(b.data);
    free(bytes);
    sl_image_free(&img);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hdr_budget_refuses_before_allocating),
        cmocka_unit_test(test_pfm_and_png_budget),
        cmocka_unit_test(test_png_zlib_bomb),
        cmocka_unit_test(test_magic_before_whole_file),
        cmocka_unit_test(test_hdr_missing_blank_line),
        cmocka_unit_test(test_hdr_old_rle),
        cmocka_unit_test(test_hdr_crlf_header),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
