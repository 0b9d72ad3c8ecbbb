/* scene_environment.c - the scene file's "environment" (docs/scene-format.md "environment"): the
 * HDR image, an optional precomputed irradiance map, the rotation, and the intensity, which is an
 * option (core/options.h) and goes into the scene's option record. */
#include "scene_read.h"

#include <math.h>

/* Degrees reduced into (-360, 360) in double, so huge-but-finite angles keep their meaning. */
static float reduce_degrees(double deg) { return (float)fmod(deg, 360.0); }

bool sl_scene_parse_environment(scene_parser *p, const cJSON *item, sl_environment_desc *env, sl_option_values *options)
{
    static const char *const keys[] = {"hdr", "irradiance", "intensity", "rotation", NULL};
    *env = (sl_environment_desc){0};
    if (!item)
        return true;
    if (cJSON_IsString(item)) /* shorthand: "environment": "envmaps/studio.hdr" */
        return sl_scene_read_path(p, item, "environment", env->hdr_path);
    if (!cJSON_IsObject(item))
        return sl_scene_fail(p, "environment", SL_ERR_FORMAT, "expected an object {\"hdr\": ...} or an .hdr path");
    if (!sl_scene_check_keys(p, item, "environment", keys))
        return false;
    const cJSON *v = sl_scene_member(item, "hdr");
    if (!v)
        return sl_scene_fail(p, "environment", SL_ERR_FORMAT, "missing \"hdr\" (the environment's .hdr image)");
    if (!sl_scene_read_path(p, v, "environment.hdr", env->hdr_path))
        return false;
    if ((v = sl_scene_member(item, "irradiance")) && !sl_scene_read_path(p, v, "environment.irradiance", env->irradiance_path))
        return false;
    if (!sl_scene_read_option(p, item, SL_OPT_ENV_INTENSITY, options))
        return false;
    double deg;
    if ((v = sl_scene_member(item, "rotation"))) {
        if (!sl_scene_read_number(p, v, "environment.rotation", &deg))
            return false;
        env->rotation_deg = reduce_degrees(deg);
    }
    return true;
}
