/* consumer.c - a program built against softlight from outside its source tree (tests/cli/install.sh,
 * tests/cli/subproject.sh): finds the studio environment in softlight's data directory, reads it,
 * clamps it to [0,1] and writes it as a PNG.
 *
 *   consumer OUT.png */
#include <stdio.h>

#if __has_include(<softlight/softlight.h>)
#include <softlight/softlight.h>
#else
/* The image functions' declarations from the source tree's src/ (given with -I) where the
 * public headers do not hold them. */
#include "core/image.h"
#endif
#include <softlight/data.h>
#include <softlight/version.h>

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: consumer OUT.png\n");
        return 2;
    }
    char env[4096];
    if (!sl_data_path("scenes/envmaps/studio.hdr", env, sizeof env)) {
        fprintf(stderr, "consumer: no softlight data directory\n");
        return 1;
    }
    sl_image img = {0};
    sl_error err = {0};
    if (!sl_image_read_hdr(env, 0, &img, NULL, &err)) {
        fprintf(stderr, "consumer: %s\n", err.msg);
        return 1;
    }
    size_t n = (size_t)img.width * (size_t)img.height * (size_t)img.channels;
    for (size_t i = 0; i < n; i++)
        img.data[i] = img.data[i] < 0.0f ? 0.0f : img.data[i] > 1.0f ? 1.0f : img.data[i];
    bool ok = sl_image_write_png(argv[1], &img, &err);
    if (ok)
        printf("softlight %s: %s (%dx%d) -> %s\n", SL_VERSION_STRING, env, img.width, img.height, argv[1]);
    else
        fprintf(stderr, "consumer: %s\n", err.msg);
    sl_image_free(&img);
    return ok ? 0 : 1;
}
