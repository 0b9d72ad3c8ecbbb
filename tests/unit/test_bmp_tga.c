/* test_bmp_tga.c - the BMP and TGA texture decoders (core/bmp_decode.c, tga_decode.c): each
 * layout a model's texture arrives in decodes to the pixels written, top row first, and each
 * damaged file is one error naming it. */
#include "testutil.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/image.h"

/* The picture every file below holds, 3x2, top row first: red, green, blue / white, black, grey. */
static const unsigned char RGB[2][3][3] = {{{255, 0, 0}, {0, 255, 0}, {0, 0, 255}},
                                           {{255, 255, 255}, {0, 0, 0}, {128, 128, 128}}};

static void put16(unsigned char *p, uint32_t v) { p[0] = (unsigned char)v, p[1] = (unsigned char)(v >> 8); }
static void put32(unsigned char *p, uint32_t v) { put16(p, v & 0xffff), put16(p + 2, v >> 16); }

static sl_raw_image decode(const unsigned char *bytes, size_t size, const char *name)
{
    sl_raw_image raw;
    sl_error err = {0};
    if (!sl_image_parse_raw(bytes, size, name, 0, NULL, &raw, &err))
        fail_msg("%s: %s", name, err.msg);
    return raw;
}

static void expect_picture(const sl_raw_image *raw, int channels)
{
    assert_int_equal(raw->width, 3);
    assert_int_equal(raw->height, 2);
    assert_int_equal(raw->channels, channels);
    assert_int_equal(raw->bits, 8);
    const unsigned char *p = raw->pixels;
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 3; x++)
            for (int c = 0; c < 3; c++)
                assert_int_equal(p[(y * 3 + x) * channels + c], RGB[y][x][c]);
}

static void expect_error(const unsigned char *bytes, size_t size, const char *name, const char *want)
{
    sl_raw_image raw;
    sl_error err = {0};
    assert_false(sl_image_parse_raw(bytes, size, name, 0, NULL, &raw, &err));
    assert_msg_contains(err, name);
    assert_msg_contains(err, want);
    assert_null(raw.pixels);
}

/* A 24-bit BMP (rows bottom-up, padded to 4 bytes) or, `top_down`, with a negative height. */
static size_t bmp24(unsigned char *b, bool top_down)
{
    memset(b, 0, 54 + 2 * 12);
    b[0] = 'B', b[1] = 'M';
    put32(b + 2, 54 + 24);
    put32(b + 10, 54);
    put32(b + 14, 40);
    put32(b + 18, 3);
    put32(b + 22, top_down ? (uint32_t)-2 : 2);
    put16(b + 26, 1);
    put16(b + 28, 24);
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 3; x++) {
            unsigned char *p = b + 54 + (top_down ? y : 1 - y) * 12 + 3 * x;
            p[0] = RGB[y][x][2], p[1] = RGB[y][x][1], p[2] = RGB[y][x][0];
        }
    return 54 + 24;
}

static void test_bmp(void **state)
{
    (void)state;
    unsigned char b[256];
    size_t n = bmp24(b, false);
    sl_raw_image raw = decode(b, n, "a.bmp");
    expect_picture(&raw, 3);
    sl_raw_image_free(&raw);
    n = bmp24(b, true);
    raw = decode(b, n, "top.bmp");
    expect_picture(&raw, 3);
    sl_raw_image_free(&raw);
    /* 8 bits through a palette of the six colours, index = y * 3 + x. */
    memset(b, 0, sizeof b);
    b[0] = 'B', b[1] = 'M';
    put32(b + 10, 54 + 6 * 4);
    put32(b + 14, 40);
    put32(b + 18, 3);
    put32(b + 22, 2);
    put16(b + 26, 1);
    put16(b + 28, 8);
    put32(b + 46, 6);
    for (int i = 0; i < 6; i++) {
        const unsigned char *c = RGB[i / 3][i % 3];
        b[54 + 4 * i] = c[2], b[55 + 4 * i] = c[1], b[56 + 4 * i] = c[0];
    }
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 3; x++)
            b[78 + (1 - y) * 4 + x] = (unsigned char)(y * 3 + x);
    raw = decode(b, 78 + 8, "palette.bmp");
    expect_picture(&raw, 3);
    sl_raw_image_free(&raw);
    /* 32 bits with BI_BITFIELDS and an alpha mask: RGBA. */
    memset(b, 0, sizeof b);
    b[0] = 'B', b[1] = 'M';
    put32(b + 10, 54 + 16);
    put32(b + 14, 40);
    put32(b + 18, 3);
    put32(b + 22, 2);
    put16(b + 26, 1);
    put16(b + 28, 32);
    put32(b + 30, 6); /* BI_ALPHABITFIELDS: four masks after the header */
    put32(b + 54, 0xff0000), put32(b + 58, 0xff00), put32(b + 62, 0xff), put32(b + 66, 0xff000000);
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 3; x++) {
            const unsigned char *c = RGB[y][x];
            put32(b + 70 + (1 - y) * 12 + 4 * x, (uint32_t)c[0] << 16 | (uint32_t)c[1] << 8 | c[2] | 0x80000000u);
        }
    raw = decode(b, 70 + 24, "alpha.bmp");
    expect_picture(&raw, 4);
    assert_int_equal(((unsigned char *)raw.pixels)[3], 128);
    sl_raw_image_free(&raw);
    /* Damaged: rows past the end, RLE, an absurd size. */
    n = bmp24(b, false);
    expect_error(b, n - 1, "cut.bmp", "truncated BMP");
    bmp24(b, false);
    put32(b + 30, 1);
    expect_error(b, n, "rle.bmp", "compressed BMP");
    bmp24(b, false);
    put32(b + 18, 0x7fffffff);
    expect_error(b, n, "wide.bmp", "BMP of 2147483647x2 pixels");
    expect_error((const unsigned char *)"BM", 2, "tiny.bmp", "truncated BMP header");
}

/* A TGA header: type, depth, descriptor (bit 5: top row first). */
static size_t tga_header(unsigned char *b, int type, int depth, int descriptor)
{
    memset(b, 0, 18);
    b[2] = (unsigned char)type;
    put16(b + 12, 3);
    put16(b + 14, 2);
    b[16] = (unsigned char)depth;
    b[17] = (unsigned char)descriptor;
    return 18;
}

static void test_tga(void **state)
{
    (void)state;
    unsigned char b[256];
    /* Uncompressed 24-bit, bottom row first. */
    size_t n = tga_header(b, 2, 24, 0);
    for (int y = 1; y >= 0; y--)
        for (int x = 0; x < 3; x++, n += 3)
            b[n] = RGB[y][x][2], b[n + 1] = RGB[y][x][1], b[n + 2] = RGB[y][x][0];
    sl_raw_image raw = decode(b, n, "plain.tga");
    expect_picture(&raw, 3);
    sl_raw_image_free(&raw);
    /* The same bytes under another name are no TGA: TGA has no signature. */
    expect_error(b, n, "plain.png", "not a PNG, JPEG, BMP or TGA file");
    expect_error(b, n - 1, "cut.tga", "truncated TGA");
    /* Run-length 32-bit, top row first: a run of two reds is not in the picture, so row 0 is
     * written as raw packets; row 1 as a raw white, a raw black and a one-pixel run of grey. */
    n = tga_header(b, 10, 32, 0x28);
    b[n++] = 0x02; /* raw packet of 3 */
    for (int x = 0; x < 3; x++, n += 4)
        b[n] = RGB[0][x][2], b[n + 1] = RGB[0][x][1], b[n + 2] = RGB[0][x][0], b[n + 3] = 255;
    b[n++] = 0x01; /* raw packet of 2 */
    for (int x = 0; x < 2; x++, n += 4)
        b[n] = RGB[1][x][2], b[n + 1] = RGB[1][x][1], b[n + 2] = RGB[1][x][0], b[n + 3] = 255;
    b[n++] = 0x80; /* run packet of 1 */
    b[n] = b[n + 1] = b[n + 2] = 128, b[n + 3] = 255;
    n += 4;
    raw = decode(b, n, "rle.TGA");
    expect_picture(&raw, 4);
    sl_raw_image_free(&raw);
    b[18] = 0x7f; /* a raw packet of 128 pixels in an image of 6 */
    expect_error(b, n, "long.tga", "TGA run past the image's end");
    /* Colour-mapped: 8-bit indices into a 24-bit map of the six colours. */
    n = tga_header(b, 1, 8, 0x20);
    b[1] = 1;
    put16(b + 5, 6);
    b[7] = 24;
    for (int i = 0; i < 6; i++, n += 3)
        b[n] = RGB[i / 3][i % 3][2], b[n + 1] = RGB[i / 3][i % 3][1], b[n + 2] = RGB[i / 3][i % 3][0];
    for (int i = 0; i < 6; i++)
        b[n++] = (unsigned char)i;
    raw = decode(b, n, "mapped.tga");
    expect_picture(&raw, 3);
    sl_raw_image_free(&raw);
    b[n - 1] = 9;
    expect_error(b, n, "index.tga", "TGA colour index outside its colour map");
    /* Grey. */
    n = tga_header(b, 3, 8, 0x20);
    for (int i = 0; i < 6; i++)
        b[n++] = (unsigned char)(40 * i);
    raw = decode(b, n, "grey.tga");
    assert_int_equal(raw.channels, 1);
    assert_int_equal(((unsigned char *)raw.pixels)[5], 200);
    sl_raw_image_free(&raw);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bmp),
        cmocka_unit_test(test_tga),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
