/* scene_lights.c - the scene file's "lights" (docs/scene-format.md "lights"): point lights, at
 * most SL_LIGHTING_MAX_LIGHTS (the lighting shader's uniform arrays), each casting shadows when
 * its "shadow" key says so (src/shadow). */
#include "scene_read.h"

#include <stdlib.h>

bool sl_scene_parse_lights(scene_parser *p, const cJSON *item, sl_scene *scene)
{
    static const char *const keys[] = {"position", "color", "intensity", "shadow", NULL};
    if (!item)
        return true;
    if (!cJSON_IsArray(item))
        return sl_scene_fail(p, "lights", SL_ERR_FORMAT, "expected an array of lights [{\"position\": ...}, ...]");
    scene->lights = calloc(SL_LIGHTING_MAX_LIGHTS, sizeof *scene->lights);
    if (!scene->lights)
        return sl_scene_fail(p, "lights", SL_ERR_MEMORY, "out of memory for %d lights", SL_LIGHTING_MAX_LIGHTS);
    for (const cJSON *e = item->child; e; e = e->next) {
        char path[JSON_PATH_MAX], sub[JSON_PATH_MAX];
        sl_scene_join_index(path, "lights", scene->light_count);
        /* The lighting shader's uniform arrays hold this many; a scene with more would pass
         * `info` and fail only when a frame is lit (even one with point lights off). */
        if (scene->light_count == SL_LIGHTING_MAX_LIGHTS)
            return sl_scene_fail(p, path, SL_ERR_RANGE, "at most %d point lights (MAX_LIGHTS of shaders/lighting.frag)",
                           SL_LIGHTING_MAX_LIGHTS);
        if (!sl_scene_check_keys(p, e, path, keys))
            return false;
        sl_point_light *l = &scene->lights[scene->light_count];
        *l = (sl_point_light){.color = vec3s(1.0f), .intensity = 1.0f};
        const cJSON *v = sl_scene_member(e, "position");
        sl_scene_join_key(sub, path, "position");
        if (!v)
            return sl_scene_fail(p, path, SL_ERR_FORMAT, "missing \"position\"");
        if (!sl_scene_read_vec3(p, v, sub, &l->position))
            return false;
        sl_scene_join_key(sub, path, "color");
        if ((v = sl_scene_member(e, "color")) && !sl_scene_read_color(p, v, sub, 1e6, &l->color))
            return false;
        sl_scene_join_key(sub, path, "intensity");
        if ((v = sl_scene_member(e, "intensity")) && !sl_scene_read_float(p, v, sub, 0.0, 1e9, &l->intensity))
            return false;
        sl_scene_join_key(sub, path, "shadow");
        if ((v = sl_scene_member(e, "shadow"))) {
            if (!cJSON_IsBool(v))
                return sl_scene_fail(p, sub, SL_ERR_FORMAT, "expected true or false");
            l->shadow = cJSON_IsTrue(v);
        }
        scene->light_count++;
    }
    return true;
}
