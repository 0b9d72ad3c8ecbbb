/* make_image_seeds.c - writes the valid PNG and JPEG seeds of fuzz/corpus/fuzz_texture (valid_*),
 * small images (at most 24x19 texels, each file under 4 KB) in every layout the decoders have a
 * path for, so that fuzz_texture starts from deep inside libpng and libjpeg-turbo instead of
 * having to discover a whole valid file first:
 *   PNG: grey 1, 4 (with a tRNS key), 8 and 16 bits; grey + alpha 8 and 16; RGB 8 (with a tRNS
 *        key) and 16; RGBA 8; palette 2 and 8 bits with tRNS; Adam7 interlaced RGB 8 and grey 16
 *   JPEG: grey baseline; colour baseline 4:2:0, 4:2:2 and 4:4:4; with restart markers; progressive
 *        grey and colour 4:2:0; Adobe CMYK and YCCK; all at quality 90
 * Every texel comes from a formula (a few gradients and a hard edge), so the files can be written
 * again bit for bit:
 *   cc -O2 fuzz/make_image_seeds.c -lpng -ljpeg -o /tmp/make_image_seeds && /tmp/make_image_seeds fuzz/corpus/fuzz_texture */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jpeglib.h>
#include <png.h>

#define W 24
#define H 19 /* odd sizes: partial MCUs, partial interlace passes */

static const char *dir;

static unsigned texel(int x, int y, int c, unsigned max)
{
    unsigned v = (unsigned)((x * 11 + y * 7 + c * 83) % 256);
    if (x > W / 2 && y > H / 3) /* a hard edge for the DCT's high frequencies */
        v = c == 1 ? 40u : 230u;
    return max == 255 ? v : v * 257u + (unsigned)(x * 3 + c);
}

static FILE *open_out(const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f) {
        perror(path);
        exit(1);
    }
    return f;
}

/* A PNG of `colour` type at `depth`; channels as stored (palette: 1); samples from texel(). */
static void png(const char *name, int colour, int depth, int interlace, const png_color_16 *key, int palette_alpha)
{
    FILE *f = open_out(name);
    png_structp p = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(p);
    if (setjmp(png_jmpbuf(p))) {
        fprintf(stderr, "%s: libpng failed\n", name);
        exit(1);
    }
    png_init_io(p, f);
    png_set_IHDR(p, info, W, H, depth, colour, interlace, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    int channels = colour == PNG_COLOR_TYPE_GRAY || colour == PNG_COLOR_TYPE_PALETTE ? 1
                   : colour == PNG_COLOR_TYPE_GRAY_ALPHA                           ? 2
                   : colour == PNG_COLOR_TYPE_RGB                                  ? 3
                                                                                   : 4;
    if (colour == PNG_COLOR_TYPE_PALETTE) {
        png_color pal[256];
        png_byte alpha[256];
        for (int i = 0; i < 256; i++) {
            pal[i] = (png_color){(png_byte)(i * 5), (png_byte)(255 - i), (png_byte)(i * 3 + 7)};
            alpha[i] = (png_byte)(255 - i * 9);
        }
        png_set_PLTE(p, info, pal, 1 << depth);
        if (palette_alpha)
            png_set_tRNS(p, info, alpha, palette_alpha, NULL);
    }
    if (key)
        png_set_tRNS(p, info, NULL, 0, key);
    png_write_info(p, info);
    if (depth < 8)
        png_set_packing(p);
    unsigned max = depth == 16 ? 65535u : (1u << depth) - 1;
    size_t bytes = depth == 16 ? 2 : 1;
    unsigned char row[W * 4 * 2];
    png_bytep rows[H];
    unsigned char *image = malloc((size_t)W * H * 4 * 2);
    for (int y = 0; y < H; y++) {
        rows[y] = image + (size_t)y * W * 4 * 2;
        for (int x = 0; x < W; x++)
            for (int c = 0; c < channels; c++) {
                unsigned v = texel(x, y, c, depth == 16 ? 65535u : 255u);
                if (depth < 8)
                    v = v * max / 255;
                if (key && (x + y) % 5 == 0) /* some texels on the transparent key */
                    v = c == 0 ? key->red : c == 1 ? key->green : key->blue;
                if (key && channels == 1 && (x + y) % 5 == 0)
                    v = key->gray;
                size_t at = ((size_t)x * (size_t)channels + (size_t)c) * bytes;
                if (bytes == 2) {
                    row[at] = (unsigned char)(v >> 8);
                    row[at + 1] = (unsigned char)v;
                } else {
                    row[at] = (unsigned char)v;
                }
            }
        memcpy(rows[y], row, (size_t)W * (size_t)channels * bytes);
    }
    png_write_image(p, rows);
    png_write_end(p, info);
    png_destroy_write_struct(&p, &info);
    free(image);
    fclose(f);
}

/* A JPEG of `components` from texel(): 1 grey, 3 RGB written as YCbCr, 4 CMYK (Adobe: as CMYK
 * or YCCK); `h`, `v`: the luma (or first component's) sampling factors. */
static void jpeg(const char *name, int components, int ycck, int h, int v, int progressive, int restart)
{
    FILE *f = open_out(name);
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr e;
    c.err = jpeg_std_error(&e);
    jpeg_create_compress(&c);
    jpeg_stdio_dest(&c, f);
    c.image_width = W;
    c.image_height = H;
    c.input_components = components;
    c.in_color_space = components == 1 ? JCS_GRAYSCALE : components == 3 ? JCS_RGB : JCS_CMYK;
    jpeg_set_defaults(&c);
    if (components == 4)
        jpeg_set_colorspace(&c, ycck ? JCS_YCCK : JCS_CMYK);
    jpeg_set_quality(&c, 90, TRUE);
    c.comp_info[0].h_samp_factor = h;
    c.comp_info[0].v_samp_factor = v;
    for (int i = 1; i < c.num_components; i++)
        c.comp_info[i].h_samp_factor = c.comp_info[i].v_samp_factor = 1;
    if (components == 4 && ycck)
        c.comp_info[3].h_samp_factor = h, c.comp_info[3].v_samp_factor = v;
    c.restart_interval = (unsigned)restart;
    if (progressive)
        jpeg_simple_progression(&c);
    jpeg_start_compress(&c, TRUE);
    unsigned char row[W * 4];
    while (c.next_scanline < H) {
        int y = (int)c.next_scanline;
        for (int x = 0; x < W; x++)
            for (int k = 0; k < components; k++)
                row[x * components + k] = (unsigned char)texel(x, y, k, 255);
        JSAMPROW r = row;
        jpeg_write_scanlines(&c, &r, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    fclose(f);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s DIR\n", argv[0]);
        return 2;
    }
    dir = argv[1];
    png_color_16 grey_key = {.gray = 3}, rgb_key = {.red = 10, .green = 200, .blue = 30};
    png("valid_grey1.png", PNG_COLOR_TYPE_GRAY, 1, PNG_INTERLACE_NONE, NULL, 0);
    png("valid_grey4_key.png", PNG_COLOR_TYPE_GRAY, 4, PNG_INTERLACE_NONE, &grey_key, 0);
    png("valid_grey8.png", PNG_COLOR_TYPE_GRAY, 8, PNG_INTERLACE_NONE, NULL, 0);
    png("valid_grey16.png", PNG_COLOR_TYPE_GRAY, 16, PNG_INTERLACE_NONE, NULL, 0);
    png("valid_grey_alpha8.png", PNG_COLOR_TYPE_GRAY_ALPHA, 8, PNG_INTERLACE_NONE, NULL, 0);
    png("valid_grey_alpha16.png", PNG_COLOR_TYPE_GRAY_ALPHA, 16, PNG_INTERLACE_NONE, NULL, 0);
    png("valid_rgb8_key.png", PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_NONE, &rgb_key, 0);
    png("valid_rgb16.png", PNG_COLOR_TYPE_RGB, 16, PNG_INTERLACE_NONE, NULL, 0);
    png("valid_rgba8.png", PNG_COLOR_TYPE_RGB_ALPHA, 8, PNG_INTERLACE_NONE, NULL, 0);
    png("valid_palette2_alpha.png", PNG_COLOR_TYPE_PALETTE, 2, PNG_INTERLACE_NONE, NULL, 3);
    png("valid_palette8_alpha.png", PNG_COLOR_TYPE_PALETTE, 8, PNG_INTERLACE_NONE, NULL, 20);
    png("valid_interlaced_rgb8.png", PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_ADAM7, NULL, 0);
    png("valid_interlaced_grey16.png", PNG_COLOR_TYPE_GRAY, 16, PNG_INTERLACE_ADAM7, NULL, 0);
    jpeg("valid_grey.jpg", 1, 0, 1, 1, 0, 0);
    jpeg("valid_420.jpg", 3, 0, 2, 2, 0, 0);
    jpeg("valid_422.jpg", 3, 0, 2, 1, 0, 0);
    jpeg("valid_444.jpg", 3, 0, 1, 1, 0, 0);
    jpeg("valid_420_restart.jpg", 3, 0, 2, 2, 0, 1);
    jpeg("valid_progressive_grey.jpg", 1, 0, 1, 1, 1, 0);
    jpeg("valid_progressive_420.jpg", 3, 0, 2, 2, 1, 0);
    jpeg("valid_cmyk.jpg", 4, 0, 1, 1, 0, 0);
    jpeg("valid_ycck.jpg", 4, 1, 2, 2, 0, 0);
    return 0;
}
