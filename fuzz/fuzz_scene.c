/* fuzz_scene.c - libFuzzer target for the scene JSON parser (from memory, meshes not loaded):
 * any bytes must give a scene or an error naming the file, in printable ASCII only (bytes of
 * the input are masked), never a crash, hang or leak. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/options.h"
#include "scene/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sl_scene scene;
    sl_error err;
    if (sl_scene_parse((const char *)data, size, "fuzz.json", "base", false, &scene, &err)) {
        /* Accepted scenes keep their invariants: indices in range, settings in range. */
        for (int i = 0; i < scene.object_count; i++)
            if (scene.objects[i].mesh < 0 || scene.objects[i].mesh >= scene.mesh_count ||
                scene.objects[i].material < 0 || scene.objects[i].material >= scene.material_count)
                abort();
        if (scene.options.samples < 1 || scene.options.samples > 1024 || !(scene.camera.znear > 0.0f) ||
            scene.light_count > SL_LIGHTING_MAX_LIGHTS)
            abort();
        sl_scene_free(&scene);
    } else if (strncmp(err.msg, "fuzz.json", 9) != 0) {
        abort(); /* every error names the file */
    } else {
        for (const char *c = err.msg; *c; c++)
            if (*c < 32 || *c > 126)
                abort(); /* a byte of the input reached the message unmasked */
    }
    return 0;
}
