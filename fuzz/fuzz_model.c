/* fuzz_model.c - libFuzzer target for the model import path (scene/model.c through assimp, and
 * gltf_check.c before it): the first byte picks the format the rest is read as (glTF JSON,
 * .glb, OBJ, OFF), as sl_model_load picks it by extension. Any bytes must give a model whose meshes
 * satisfy the mesh contract, or one line of error: never a crash, hang or leak. assimp itself is
 * not instrumented (Debian's build), so coverage guides through softlight's side only. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "scene/model.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const hints[] = {"gltf", "glb", "obj", "off"};
    if (size < 1)
        return 0;
    const char *hint = hints[data[0] % 4];
    sl_model model;
    sl_error err;
    if (sl_model_load_memory(data + 1, size - 1, hint, "fuzz", &model, &err)) {
        for (int i = 0; i < model.mesh_count; i++)
            if (!sl_mesh_validate(&model.meshes[i].mesh, "fuzz", &err))
                abort();
        for (int i = 0; i < model.instance_count; i++)
            if (model.instances[i].mesh < 0 || model.instances[i].mesh >= model.mesh_count)
                abort();
        sl_model_free(&model);
    } else if (strchr(err.msg, '\n')) {
        abort(); /* one line */
    }
    return 0;
}
