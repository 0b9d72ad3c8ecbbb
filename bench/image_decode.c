/* image_decode.c - bench_image_decode: PNG and JPEG texture decoding, softlight's decoders
 * (sl_image_parse_raw: libpng, libjpeg-turbo) against stb_image 2.27 (Debian 12's libstb-dev),
 * for speed and for agreement (not a test).
 *
 * Timing: a 3840x2160 picture (smooth gradients, edges and a little noise, made here) written
 * as an 8-bit RGB PNG (softlight's own PNG writer) and as a quality 90 JPEG (libjpeg-turbo,
 * 4:2:0, baseline); each file is decoded --rounds times by each decoder, alternating, one
 * thread, and the median milliseconds are printed. The files are decoded from memory, so the
 * figures exclude reading the file.
 *
 * Agreement: for each picture decoded, the two decoders' outputs are compared byte for byte:
 * size, channels and bits must match; the largest difference of one sample and how many
 * samples differ are printed. PNG decoding is exact, so any difference there is a bug. For
 * JPEG the IDCT, chroma upsampling and colour conversion are each decoder's own, so codes may
 * differ by a little. `--compare FILE...` does the same for the given PNG and JPEG files, and
 * for each 8-bit PNG among them also for that picture encoded as JPEG at quality 90 (baseline
 * 4:2:0, baseline 4:4:4, progressive 4:2:0).
 *
 * usage: bench_image_decode [--rounds 5] [--compare FILE...] */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jpeglib.h>

#include "core/image.h"
#include "core/timer.h"

/* stb is third-party code: its own warnings are not ours to fix. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#define W 3840
#define H 2160
#define MAX_ROUNDS 64

typedef struct {
    int width, height, channels, bits;
    void *pixels;
} decoded;

static bool decode_stb(const unsigned char *bytes, size_t size, decoded *out)
{
    int w = 0, h = 0, n = 0;
    bool wide = stbi_is_16_bit_from_memory(bytes, (int)size);
    void *p = wide ? (void *)stbi_load_16_from_memory(bytes, (int)size, &w, &h, &n, 0)
                   : (void *)stbi_load_from_memory(bytes, (int)size, &w, &h, &n, 0);
    *out = (decoded){w, h, n, wide ? 16 : 8, p};
    return p != NULL;
}

static bool decode_sl(const unsigned char *bytes, size_t size, decoded *out)
{
    *out = (decoded){0};
    sl_raw_image raw;
    sl_error err = {0};
    if (!sl_image_parse_raw(bytes, size, "bench", (size_t)4 << 30, NULL, &raw, &err)) {
        printf("  softlight: %s\n", err.msg);
        return false;
    }
    *out = (decoded){raw.width, raw.height, raw.channels, raw.bits, raw.pixels};
    return true;
}

/* A JPEG of 8-bit grey or RGB pixels at quality 90: `h` x `v` luma sampling, progressive or not. */
static bool encode_jpeg(const unsigned char *pixels, int w, int h, int channels, int hs, int vs, bool progressive,
                        unsigned char **bytes, size_t *size)
{
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr e;
    c.err = jpeg_std_error(&e);
    jpeg_create_compress(&c);
    unsigned long n = 0;
    *bytes = NULL;
    jpeg_mem_dest(&c, bytes, &n);
    c.image_width = (JDIMENSION)w;
    c.image_height = (JDIMENSION)h;
    c.input_components = channels;
    c.in_color_space = channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 90, TRUE);
    c.comp_info[0].h_samp_factor = hs;
    c.comp_info[0].v_samp_factor = vs;
    if (progressive)
        jpeg_simple_progression(&c);
    jpeg_start_compress(&c, TRUE);
    while (c.next_scanline < c.image_height) {
        JSAMPROW row = (JSAMPROW)(pixels + (size_t)c.next_scanline * (size_t)w * (size_t)channels);
        jpeg_write_scanlines(&c, &row, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    *size = n;
    return n > 0;
}

/* Both decoders on one file: prints the largest sample difference; false if they disagree on
 * the layout or either fails. */
static bool compare(const char *what, const unsigned char *bytes, size_t size, int *max_diff)
{
    decoded a, b;
    bool ok_a = decode_stb(bytes, size, &a), ok_b = decode_sl(bytes, size, &b);
    if (!ok_a || !ok_b) {
        printf("%-44s stb %s, softlight %s\n", what, ok_a ? "decodes" : stbi_failure_reason(),
               ok_b ? "decodes" : "fails");
        stbi_image_free(a.pixels);
        free(b.pixels);
        return false;
    }
    if (a.width != b.width || a.height != b.height || a.channels != b.channels || a.bits != b.bits) {
        printf("%-44s layout differs: stb %dx%d x%d %d-bit, softlight %dx%d x%d %d-bit\n", what, a.width, a.height,
               a.channels, a.bits, b.width, b.height, b.channels, b.bits);
        stbi_image_free(a.pixels);
        free(b.pixels);
        return false;
    }
    size_t count = (size_t)a.width * (size_t)a.height * (size_t)a.channels, differ = 0;
    int worst = 0;
    for (size_t i = 0; i < count; i++) {
        int va = a.bits == 16 ? ((const uint16_t *)a.pixels)[i] : ((const unsigned char *)a.pixels)[i];
        int vb = b.bits == 16 ? ((const uint16_t *)b.pixels)[i] : ((const unsigned char *)b.pixels)[i];
        int d = va > vb ? va - vb : vb - va;
        differ += d != 0;
        worst = d > worst ? d : worst;
    }
    printf("%-44s %dx%d x%d %2d-bit: max difference %d, %zu of %zu samples differ (%.3f%%)\n", what, a.width,
           a.height, a.channels, a.bits, worst, differ, count, count ? 100.0 * (double)differ / (double)count : 0.0);
    if (worst > *max_diff)
        *max_diff = worst;
    stbi_image_free(a.pixels);
    free(b.pixels);
    return true;
}

static bool read_whole(const char *path, unsigned char **bytes, size_t *size)
{
    sl_error err = {0};
    if (!sl_read_file(path, (size_t)1 << 30, bytes, size, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return false;
    }
    return true;
}

/* The file, and for an 8-bit grey or colour PNG the same picture as three kinds of JPEG. */
static bool compare_file(const char *path, int *max_png, int *max_jpeg)
{
    unsigned char *bytes;
    size_t size;
    if (!read_whole(path, &bytes, &size))
        return false;
    bool png = size > 0 && bytes[0] == 0x89, ok = compare(path, bytes, size, png ? max_png : max_jpeg);
    decoded a;
    if (ok && png && decode_stb(bytes, size, &a) && a.bits == 8) {
        int colour = a.channels >= 3 ? 3 : 1;
        unsigned char *plain = malloc((size_t)a.width * (size_t)a.height * (size_t)colour);
        for (size_t i = 0; i < (size_t)a.width * (size_t)a.height; i++)
            for (int c = 0; c < colour; c++)
                plain[i * (size_t)colour + (size_t)c] = ((unsigned char *)a.pixels)[i * (size_t)a.channels + (size_t)c];
        static const struct {
            int h, v;
            bool progressive;
            const char *name;
        } kinds[3] = {{2, 2, false, "q90 4:2:0"}, {1, 1, false, "q90 4:4:4"}, {2, 2, true, "q90 4:2:0 progressive"}};
        for (int k = 0; k < 3; k++) {
            unsigned char *jpeg;
            size_t jsize;
            char what[300];
            const char *base = strrchr(path, '/');
            snprintf(what, sizeof what, "  as JPEG %s (%s)", kinds[k].name, base ? base + 1 : path);
            if (encode_jpeg(plain, a.width, a.height, colour, kinds[k].h, kinds[k].v, kinds[k].progressive, &jpeg,
                            &jsize))
                ok = compare(what, jpeg, jsize, max_jpeg) && ok;
            free(jpeg);
        }
        free(plain);
        stbi_image_free(a.pixels);
    }
    free(bytes);
    return ok;
}

/* The timed picture: gradients, a grid of hard edges, and a little noise (so that PNG's filters
 * and deflate, and JPEG's AC coefficients, have work like a photograph's). */
static unsigned char *picture(void)
{
    unsigned char *p = malloc((size_t)W * H * 3);
    uint32_t state = 12345u;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            state = state * 1664525u + 1013904223u;
            int noise = (int)(state >> 29) - 4;
            bool edge = ((x / 240) + (y / 240)) % 2 == 0;
            int v[3] = {x * 255 / W, y * 255 / H, edge ? 200 : 60};
            for (int c = 0; c < 3; c++) {
                int t = v[c] + noise;
                p[((size_t)y * W + (size_t)x) * 3 + (size_t)c] = (unsigned char)(t < 0 ? 0 : t > 255 ? 255 : t);
            }
        }
    return p;
}

int main(int argc, char **argv)
{
    int rounds = 5, first_file = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--rounds") && i + 1 < argc) {
            rounds = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--compare") && i + 1 < argc) {
            first_file = i + 1;
            break;
        } else {
            fprintf(stderr, "usage: bench_image_decode [--rounds 5] [--compare FILE...]\n");
            return 2;
        }
    }
    if (rounds < 1 || rounds > MAX_ROUNDS) {
        fprintf(stderr, "bench_image_decode: --rounds must be 1..%d\n", MAX_ROUNDS);
        return 2;
    }
    int max_png = 0, max_jpeg = 0;
    bool ok = true;
    if (first_file) {
        for (int i = first_file; i < argc; i++)
            ok = compare_file(argv[i], &max_png, &max_jpeg) && ok;
        printf("largest difference: PNG %d, JPEG %d (codes)\n", max_png, max_jpeg);
        return ok ? 0 : 1;
    }

    unsigned char *pixels = picture();
    sl_image img;
    sl_error err = {0};
    if (!sl_image_alloc(&img, W, H, 3, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    for (size_t i = 0; i < (size_t)W * H * 3; i++)
        img.data[i] = pixels[i] / 255.0f;
    unsigned char *files[2];
    size_t sizes[2];
    if (!sl_image_encode_png(&img, &files[0], &sizes[0], &err) ||
        !encode_jpeg(pixels, W, H, 3, 2, 2, false, &files[1], &sizes[1])) {
        fprintf(stderr, "bench_image_decode: encoding failed %s\n", err.msg);
        return 1;
    }
    sl_image_free(&img);
    free(pixels);
    static const char *names[2] = {"PNG 8-bit RGB", "JPEG q90 4:2:0"};
    printf("%dx%d, %d rounds, decoding from memory, one thread\n", W, H, rounds);
    for (int f = 0; f < 2; f++) {
        double t_stb[MAX_ROUNDS], t_sl[MAX_ROUNDS];
        for (int r = 0; r < rounds; r++)
            for (int which = 0; which < 2; which++) { /* alternating: stb, then softlight, each round */
                decoded d;
                double t0 = sl_now_seconds();
                bool done = which == 0 ? decode_stb(files[f], sizes[f], &d) : decode_sl(files[f], sizes[f], &d);
                double t = sl_now_seconds() - t0;
                if (!done) {
                    fprintf(stderr, "bench_image_decode: %s: decoding failed\n", names[f]);
                    return 1;
                }
                if (which == 0) {
                    stbi_image_free(d.pixels);
                    t_stb[r] = t;
                } else {
                    free(d.pixels);
                    t_sl[r] = t;
                }
            }
        double stb = sl_median(t_stb, rounds) * 1e3, sl = sl_median(t_sl, rounds) * 1e3;
        printf("%-16s %8.1f KB  stb_image %7.1f ms  libpng/libjpeg-turbo %7.1f ms  (ratio %.2f)\n", names[f],
               (double)sizes[f] / 1024.0, stb, sl, sl / stb);
    }
    for (int f = 0; f < 2; f++)
        ok = compare(names[f], files[f], sizes[f], f == 0 ? &max_png : &max_jpeg) && ok;
    free(files[0]);
    free(files[1]);
    return ok && max_png == 0 ? 0 : 1;
}
