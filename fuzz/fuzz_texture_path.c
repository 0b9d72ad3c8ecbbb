/* fuzz_texture_path.c - libFuzzer target for texture path resolution (scene/texture_path.c):
 * any bytes as a material's texture reference, resolved against a folder holding a few files
 * in mixed case and a subfolder. A reference resolves to a regular file or to nothing: never a
 * crash, an unterminated path or a write past the path's buffer. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scene/scene_internal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *folder(void)
{
    static char dir[64];
    if (dir[0])
        return dir;
    snprintf(dir, sizeof dir, "/tmp/sl-fuzz-texpath-%d/", (int)getpid());
    char path[128];
    mkdir(dir, 0755);
    snprintf(path, sizeof path, "%sMaps", dir);
    mkdir(path, 0755);
    static const char *const files[] = {"Wood.png", "Maps/bark.JPG", "a b.tga"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        snprintf(path, sizeof path, "%s%s", dir, files[i]);
        FILE *f = fopen(path, "wb");
        if (f)
            fclose(f);
    }
    return dir;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char ref[2 * SL_PATH_MAX];
    if (size >= sizeof ref)
        size = sizeof ref - 1;
    memcpy(ref, data, size);
    ref[size] = '\0';
    char out[SL_PATH_MAX];
    if (scene_texture_path_resolve(folder(), ref, out)) {
        struct stat st;
        if (strnlen(out, sizeof out) == sizeof out || stat(out, &st) != 0 || !S_ISREG(st.st_mode))
            abort();
    }
    return 0;
}
