/* fuzz_obj.c - libFuzzer target for the OBJ reader: any bytes must give a validated mesh or
 * an error, never a crash, hang, leak or NaN normal. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "scene/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sl_mesh mesh;
    sl_error err;
    if (sl_mesh_parse_obj((const char *)data, size, "fuzz.obj", &mesh, &err)) {
        /* Whatever the reader accepts must satisfy the mesh contract. */
        if (!sl_mesh_validate(&mesh, "fuzz.obj", &err))
            abort();
        sl_mesh_free(&mesh);
    }
    return 0;
}
