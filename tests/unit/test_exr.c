/* test_exr.c - OpenEXR through OpenEXRCore (src/core/exr.c): files written through the library
 * (float and half, scanline and tiled, every lossless compression, RGBA, grey Y, layers) read
 * back with exact values; the environment reader's refusals (no RGB, luminance/chroma, deep,
 * truncated, corrupt); the reader picked by content for environments.
 *
 * Expected values: floats come back bit for bit; halves are values a half holds exactly
 * (k/8, 65504) or the rounding of 0.1 worked out by hand (0x2E66 = 1.599609375 * 2^-4). */
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/exr.h"
#include "core/image.h"

/* An image whose texel (x, y, c) is a distinct value a half holds exactly: (x + 8 y + c) / 8, up
 * to 2^11 / 8 = 256 before its step exceeds 1/8, so keep x + 8y + c below 2048. */
static void ramp(sl_image *img, int w, int h, int channels)
{
    assert_true(sl_image_alloc(img, w, h, channels, NULL));
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < channels; c++)
                sl_image_pixel(img, x, y)[c] = (float)(x + 8 * y + c) / 8.0f;
}

static void encode(const sl_exr_layer *layers, int count, sl_exr_options o, unsigned char **bytes, size_t *size)
{
    sl_error err = {0};
    if (!sl_exr_encode(layers, count, &o, bytes, size, &err))
        fail_msg("%s", err.msg);
}

static void read_env(const unsigned char *bytes, size_t size, sl_image *img, sl_image_repairs *rep)
{
    sl_error err = {0};
    if (!sl_image_parse_exr(bytes, size, "t.exr", 0, img, rep, &err))
        fail_msg("%s", err.msg);
}

/* RGB through every lossless compression, scanline and tiled (tiles 16x16 over 37x23, so edge
 * tiles are partial), float and half: what was written comes back bit for bit. */
static void test_round_trip_compressions(void **state)
{
    (void)state;
    static const sl_exr_compression lossless[] = {SL_EXR_NONE, SL_EXR_RLE, SL_EXR_ZIPS, SL_EXR_ZIP, SL_EXR_PIZ};
    sl_image src;
    ramp(&src, 37, 23, 3);
    for (size_t i = 0; i < sizeof lossless / sizeof lossless[0]; i++) {
        for (int tile = 0; tile <= 16; tile += 16) {
            for (int half = 0; half < 2; half++) {
                unsigned char *bytes;
                size_t size;
                sl_exr_layer layer = {"", "RGB", &src};
                encode(&layer, 1, (sl_exr_options){.half = half, .compression = lossless[i], .tile = tile}, &bytes, &size);
                sl_image back;
                sl_image_repairs rep;
                read_env(bytes, size, &back, &rep);
                assert_same_image(&back, &src, "compression %d tile %d half %d", (int)lossless[i], tile, half);
                assert_int_equal(rep.nan_count + rep.inf_count + rep.negative_count, 0);
                sl_image_free(&back);
                free(bytes);
            }
        }
    }
    sl_image_free(&src);
}

/* Chunks that compress to exactly their raw size: OpenEXRCore 3.1 stored the compressed bytes,
 * which every reader takes as raw (sizes equal), so the image read back as zlib streams. Small
 * noisy images hit it: with the library's writer as it is, 95 of these 6000 failed. Each must
 * come back bit for bit (sizes 1..9 x 1..40, four compressions, scanline and tiled). */
static void test_round_trip_incompressible_chunks(void **state)
{
    (void)state;
    static const sl_exr_compression compressions[] = {SL_EXR_RLE, SL_EXR_ZIPS, SL_EXR_ZIP, SL_EXR_PIZ};
    uint32_t rng = 12345;
#define NEXT() (rng = rng * 1664525u + 1013904223u)
    for (int it = 0; it < 6000; it++) {
        int w = 1 + (int)(NEXT() % 9), h = 1 + (int)(NEXT() % 40);
        sl_exr_options o = {.compression = compressions[NEXT() % 4]};
        o.tile = NEXT() % 2 ? (int)(1 + NEXT() % 8) : 0;
        sl_image img, back;
        assert_true(sl_image_alloc(&img, w, h, 3, NULL));
        uint32_t kind = NEXT() % 4;
        for (int i = 0; i < w * h * 3; i++) { /* any finite bits, subnormals, mostly zeros, near 1 */
            uint32_t bits = kind == 0 ? NEXT() & 0x7fffffffu
                            : kind == 1 ? NEXT() % 0x00800000u
                            : kind == 2 ? (NEXT() % 3 ? 0u : NEXT() & 0x7fffffu)
                                        : 0x3f800000u + NEXT() % 1000u;
            memcpy(&img.data[i], &bits, sizeof bits);
            if (!isfinite(img.data[i]))
                img.data[i] = 1.0f;
        }
        unsigned char *bytes;
        size_t size;
        sl_exr_layer layer = {"", "RGB", &img};
        encode(&layer, 1, o, &bytes, &size);
        read_env(bytes, size, &back, NULL);
        if (memcmp(back.data, img.data, (size_t)w * (size_t)h * 3 * sizeof(float)) != 0)
            fail_msg("image %d (%dx%d, compression %d, tile %d) did not come back bit for bit", it, w, h,
                     (int)o.compression, o.tile);
        sl_image_free(&back);
        sl_image_free(&img);
        free(bytes);
    }
#undef NEXT
}

/* Half rounding and range, by hand: 0.1 -> 0x2E66 = 0.0999755859375; 65504 is the largest half;
 * 1e5 overflows to +Inf, which the environment reader repairs to 0 and counts; -2 is a negative
 * texel (repaired); NaN stays NaN in half and is repaired. PXR24 is lossless for half. */
static void test_half_values_and_repairs(void **state)
{
    (void)state;
    sl_image src;
    assert_true(sl_image_alloc(&src, 2, 2, 3, NULL));
    const float v[12] = {0.1f, 65504.0f, 1.0f, 1e5f, 0.5f, 0.25f, -2.0f, 3.0f, 4.0f, NAN, 1.5f, 0.0f};
    memcpy(src.data, v, sizeof v);
    for (int c = 0; c < 2; c++) {
        unsigned char *bytes;
        size_t size;
        sl_exr_layer layer = {"", "RGB", &src};
        encode(&layer, 1, (sl_exr_options){.half = true, .compression = c ? SL_EXR_PXR24 : SL_EXR_ZIP}, &bytes, &size);
        sl_image back;
        sl_image_repairs rep;
        read_env(bytes, size, &back, &rep);
        const float want[12] = {0.0999755859375f, 65504.0f, 1.0f, 0.0f, 0.5f, 0.25f, 0.0f, 3.0f, 4.0f, 0.0f, 1.5f, 0.0f};
        for (int k = 0; k < 12; k++)
            assert_true(back.data[k] == want[k]);
        assert_int_equal(rep.inf_count, 1);
        assert_int_equal(rep.negative_count, 1);
        assert_int_equal(rep.nan_count, 1);
        sl_image_free(&back);
        free(bytes);
    }
    sl_image_free(&src);
}

/* RGBA: alpha is ignored. A lone Y is grey, replicated into R, G, B. B44A on a flat image (each
 * 4x4 block one value) is exact. */
static void test_rgba_and_grey(void **state)
{
    (void)state;
    sl_image rgba, grey, back;
    ramp(&rgba, 9, 7, 4);
    unsigned char *bytes;
    size_t size;
    sl_exr_layer layer = {"", "RGBA", &rgba};
    encode(&layer, 1, (sl_exr_options){.compression = SL_EXR_ZIP, .tile = 4}, &bytes, &size);
    read_env(bytes, size, &back, NULL);
    assert_int_equal(back.channels, 3);
    for (int y = 0; y < 7; y++)
        for (int x = 0; x < 9; x++)
            for (int c = 0; c < 3; c++)
                assert_true(sl_image_pixel(&back, x, y)[c] == sl_image_pixel(&rgba, x, y)[c]);
    sl_image_free(&back);
    free(bytes);

    assert_true(sl_image_alloc(&grey, 8, 8, 1, NULL));
    for (int i = 0; i < 64; i++)
        grey.data[i] = 2.5f;
    layer = (sl_exr_layer){"Y", "", &grey};
    encode(&layer, 1, (sl_exr_options){.half = true, .compression = SL_EXR_B44A}, &bytes, &size);
    read_env(bytes, size, &back, NULL);
    assert_int_equal(back.channels, 3);
    for (int i = 0; i < 64 * 3; i++)
        assert_true(back.data[i] == 2.5f);
    sl_image_free(&back);
    free(bytes);
    sl_image_free(&grey);

    /* Channels the reader does not keep (B and G beside a lone Y: grey) are decoded and dropped;
     * OpenEXRCore's own "skip this channel" crashed on a tiled RLE file of this shape (fuzz_exr,
     * fuzz/corpus/fuzz_exr/tiled_rle_unused_channels.exr). */
    layer = (sl_exr_layer){"", "BGY", &rgba};
    sl_image bgy;
    ramp(&bgy, 9, 7, 3);
    layer.img = &bgy;
    encode(&layer, 1, (sl_exr_options){.half = true, .compression = SL_EXR_RLE, .tile = 4}, &bytes, &size);
    read_env(bytes, size, &back, NULL);
    for (int y = 0; y < 7; y++)
        for (int x = 0; x < 9; x++)
            for (int c = 0; c < 3; c++)
                assert_true(sl_image_pixel(&back, x, y)[c] == sl_image_pixel(&bgy, x, y)[2]);
    sl_image_free(&back);
    free(bytes);
    sl_image_free(&bgy);
    sl_image_free(&rgba);
}

/* Layers: names follow layer.channel; each reads back by name with signed values kept, and the
 * default layer is what the environment reader takes. */
static void test_layers(void **state)
{
    (void)state;
    sl_image rgb, normal, depth;
    ramp(&rgb, 5, 4, 3);
    ramp(&normal, 5, 4, 3);
    for (int i = 0; i < 60; i++)
        normal.data[i] = -normal.data[i];
    ramp(&depth, 5, 4, 1);
    sl_exr_layer layers[] = {{"", "RGB", &rgb}, {"normal", "XYZ", &normal}, {"depth", "", &depth}};
    unsigned char *bytes;
    size_t size;
    encode(layers, 3, (sl_exr_options){.compression = SL_EXR_ZIP}, &bytes, &size);
    sl_image back;
    sl_error err = {0};
    assert_true(sl_exr_parse_layer(bytes, size, "normal", "XYZ", 0, &back, &err));
    assert_same_image(&back, &normal, "normal layer");
    sl_image_free(&back);
    assert_true(sl_exr_parse_layer(bytes, size, "depth", "", 0, &back, &err));
    assert_same_image(&back, &depth, "depth");
    sl_image_free(&back);
    read_env(bytes, size, &back, NULL);
    assert_same_image(&back, &rgb, "default layer");
    sl_image_free(&back);
    assert_false(sl_exr_parse_layer(bytes, size, "kd", "RGB", 0, &back, &err));
    assert_msg_contains(err, "no channel kd.R");
    assert_msg_contains(err, "normal.X");
    free(bytes);

    /* a file with no R, G, B nor Y is refused, listing what it has */
    encode(&layers[1], 2, (sl_exr_options){0}, &bytes, &size);
    assert_false(sl_image_parse_exr(bytes, size, "n.exr", 0, &back, NULL, &err));
    assert_msg_contains(err, "n.exr: no R, G, B channels (nor a grey Y) in the first part; it has 4 channels: depth, normal.X");
    free(bytes);

    /* two channels of one name, and images of different sizes, are the writer's errors */
    sl_exr_layer twice[] = {{"", "RGB", &rgb}, {"", "RGB", &rgb}};
    assert_false(sl_exr_encode(twice, 2, NULL, &bytes, &size, &err));
    assert_msg_contains(err, "two channels named 'R'");
    sl_image small;
    ramp(&small, 2, 2, 3);
    sl_exr_layer sizes[] = {{"", "RGB", &rgb}, {"kd", "RGB", &small}};
    assert_false(sl_exr_encode(sizes, 2, NULL, &bytes, &size, &err));
    assert_msg_contains(err, "layer 'kd'");
    sl_image_free(&small);
    sl_image_free(&rgb);
    sl_image_free(&normal);
    sl_image_free(&depth);
}

/* Luminance/chroma files are refused with a reason; a lone Y with RY, BY is not read as grey. */
static void test_luminance_chroma_refused(void **state)
{
    (void)state;
    sl_image y, back;
    ramp(&y, 4, 4, 1);
    sl_exr_layer layers[] = {{"Y", "", &y}, {"RY", "", &y}, {"BY", "", &y}};
    unsigned char *bytes;
    size_t size;
    encode(layers, 3, (sl_exr_options){.half = true}, &bytes, &size);
    sl_error err = {0};
    assert_false(sl_image_parse_exr(bytes, size, "yc.exr", 0, &back, NULL, &err));
    assert_msg_contains(err, "yc.exr: luminance/chroma channels (Y, RY, BY) are not read");
    free(bytes);
    sl_image_free(&y);
}

/* Every prefix of a valid file, and the file with bytes flipped in its chunk table and data, is
 * an error naming the file (never a crash: the ASan build runs this), and a too-small budget is
 * refused before the image is allocated. */
static void test_truncated_and_corrupt(void **state)
{
    (void)state;
    sl_image src, back;
    ramp(&src, 40, 30, 3);
    unsigned char *bytes;
    size_t size;
    sl_exr_layer layer = {"", "RGB", &src};
    encode(&layer, 1, (sl_exr_options){.compression = SL_EXR_ZIP}, &bytes, &size);
    sl_error err = {0};
    for (size_t n = 0; n < size; n += n < 400 ? 1 : 97) {
        if (sl_image_parse_exr(bytes, n, "cut.exr", 0, &back, NULL, &err))
            fail_msg("a file cut at %zu of %zu bytes was read", n, size);
        assert_msg_contains(err, "cut.exr: ");
        assert_null(back.data);
    }
    unsigned char *bad = malloc(size);
    assert_non_null(bad);
    int failures = 0;
    for (size_t at = 8; at < size; at += 7) {
        memcpy(bad, bytes, size);
        bad[at] ^= 0x5a;
        if (!sl_image_parse_exr(bad, size, "flip.exr", 0, &back, NULL, &err)) {
            assert_msg_contains(err, "flip.exr: ");
            failures++;
        }
        sl_image_free(&back);
    }
    assert_true(failures > 0);
    free(bad);
    assert_false(sl_image_parse_exr(bytes, size, "big.exr", 4096, &back, NULL, &err));
    assert_msg_contains(err, "big.exr: byte 8: image 40x30 needs");
    assert_msg_contains(err, "--image-memory");
    /* the fuzzer's tiled RLE file whose unused channels crashed the library's skip path */
    unsigned char *found;
    size_t found_size;
    assert_true(sl_read_file("fuzz/corpus/fuzz_exr/tiled_rle_unused_channels.exr", 1 << 20, &found, &found_size, &err));
    if (!sl_image_parse_exr(found, found_size, "fuzzed.exr", 0, &back, NULL, &err))
        assert_msg_contains(err, "fuzzed.exr: ");
    sl_image_free(&back);
    free(found);
    const unsigned char not_exr[8] = {'#', '?', 'R', 'A', 'D', 'I', 'A', 'N'};
    assert_false(sl_image_parse_exr(not_exr, sizeof not_exr, "x.exr", 0, &back, NULL, &err));
    assert_msg_contains(err, "x.exr: byte 0: not an OpenEXR file: expected the magic 76 2f 31 01, found 23 3f 52 41");
    free(bytes);
    sl_image_free(&src);
}

/* The environment reader goes by content: an .exr named .hdr reads as OpenEXR, a PFM named .exr
 * as PFM, and an .hdr keeps its reader (and its messages). */
static void test_read_radiance_by_content(void **state)
{
    (void)state;
    sl_image src, back;
    ramp(&src, 6, 3, 3);
    sl_error err = {0};
    const char *as_hdr = test_tmpfile("really-exr.hdr"), *as_exr = test_tmpfile("really-pfm.exr");
    assert_true(sl_image_write_with(as_hdr, sl_image_encode_exr, &src, &err));
    assert_true(sl_image_write_pfm(as_exr, &src, &err));
    assert_true(sl_image_read_radiance(as_hdr, 0, &back, NULL, &err));
    assert_same_image(&back, &src, "exr named .hdr");
    sl_image_free(&back);
    assert_true(sl_image_read_radiance(as_exr, 0, &back, NULL, &err));
    assert_same_image(&back, &src, "pfm named .exr");
    sl_image_free(&back);
    assert_true(sl_image_read_radiance("scenes/envmaps/studio.hdr", 0, &back, NULL, &err));
    sl_image_free(&back);
    const char *empty = test_tmpfile("empty.exr");
    test_write_bytes(empty, "", 0);
    assert_false(sl_image_read_radiance(empty, 0, &back, NULL, &err));
    assert_msg_contains(err, "empty.exr: byte 0: unexpected end of file, expected the OpenEXR magic");
    sl_image_free(&src);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip_compressions), cmocka_unit_test(test_round_trip_incompressible_chunks),
        cmocka_unit_test(test_half_values_and_repairs),
        cmocka_unit_test(test_rgba_and_grey),           cmocka_unit_test(test_layers),
        cmocka_unit_test(test_luminance_chroma_refused), cmocka_unit_test(test_truncated_and_corrupt),
        cmocka_unit_test(test_read_radiance_by_content),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
