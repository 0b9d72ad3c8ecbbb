/* scene_api.c - the public scene handle (softlight/scene.h) on top of sl_scene_load. */
#include <stdlib.h>

#include "scene.h"

sl_scene *sl_scene_open(const char *path, sl_error *err)
{
    sl_scene *scene = calloc(1, sizeof *scene);
    if (!scene) {
        sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for the scene", path);
        return NULL;
    }
    if (!sl_scene_load(path, scene, err)) {
        free(scene);
        return NULL;
    }
    return scene;
}

void sl_scene_close(sl_scene *scene)
{
    if (!scene)
        return;
    sl_scene_free(scene);
    free(scene);
}

sl_camera sl_scene_camera(const sl_scene *scene) { return scene->camera; }
const char *sl_scene_warnings(const sl_scene *scene) { return scene->warnings; }
