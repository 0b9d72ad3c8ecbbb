/* scene_materials.c - the scene file's "materials" (docs/scene-format.md "materials"): each
 * material's constants, its BRDF, glTF's metallic-roughness, occlusion and emission keys, and its
 * texture maps, whose image files become the scene's images (one per file and colour space); the
 * lookup of a material by name, and the built-in default material. */
#include "scene_read.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Limits on values that are legal JSON but absurd for a frame. */
#define MAX_ALPHA 1e6
/* GGX roughness is glTF's perceptual roughness, in [0, 1] by definition; default 0.5. */
#define MAX_ROUGHNESS 1.0
#define DEFAULT_ROUGHNESS 0.5f

static int compare_names(const void *a, const void *b)
{
    return strcmp(((const scene_name_index *)a)->name, ((const scene_name_index *)b)->name);
}

/* ---- texture maps (docs/scene-format.md "Texture maps") ---- */

const char *const sl_scene_map_keys[SL_MAP_COUNT] = {"kd_map",   "ks_map",   "alpha_map",
                                                   "normal_map", "mask_map", "metallic_roughness_map",
                                                   "occlusion_map", "emissive_map"};
/* Colour maps are sRGB by default (what image editors write, glTF's rule); data maps are linear. */
static const bool MAP_SRGB_DEFAULT[SL_MAP_COUNT] = {true, true, false, false, false, false, false, true};
/* Emitted radiance: far above a lamp's in the shipped environments, far below float overflow
 * once summed with the image-based terms. */
#define MAX_EMISSIVE 1e4
/* uv_scale and uv_offset: beyond this a float texture coordinate keeps too few fraction bits
 * (2^-10 of a repeat at 1e4) for a filtered lookup to mean anything. */
#define MAX_UV_TRANSFORM 1e4

/* The scene's image for (path, srgb), added on first use: one file, one texture, however many
 * maps name it. */
static bool scene_image(scene_parser *p, sl_scene *scene, const char *file, bool srgb, const char *path, int *index)
{
    for (int i = 0; i < scene->image_count; i++) {
        if (scene->images[i].srgb == srgb && strcmp(scene->images[i].path, file) == 0) {
            *index = i;
            return true;
        }
    }
    if (scene->image_count == SL_SCENE_MAX_IMAGES)
        return sl_scene_fail(p, path, SL_ERR_RANGE, "more than %d distinct image files in one scene", SL_SCENE_MAX_IMAGES);
    if (!scene->images && !(scene->images = calloc(SL_SCENE_MAX_IMAGES, sizeof *scene->images)))
        return sl_scene_fail(p, path, SL_ERR_MEMORY, "out of memory for the image table");
    sl_scene_image *img = &scene->images[scene->image_count];
    snprintf(img->path, sizeof img->path, "%s", file);
    img->srgb = srgb;
    _Static_assert(sizeof img->used_by == JSON_PATH_MAX, "a JSON path fits in used_by");
    memcpy(img->used_by, path, strlen(path) + 1);
    *index = scene->image_count++;
    return true;
}

static bool read_uv_pair(scene_parser *p, const cJSON *item, const char *path, vec2 *out)
{
    double v[2];
    if (!sl_scene_read_numbers(p, item, path, 2, v))
        return false;
    for (int i = 0; i < 2; i++)
        if (fabs(v[i]) > MAX_UV_TRANSFORM)
            return sl_scene_fail(p, path, SL_ERR_RANGE, "%g is outside -%g..%g", v[i], MAX_UV_TRANSFORM, MAX_UV_TRANSFORM);
    *out = vec2(v[0], v[1]);
    return true;
}

/* One enumerated string among `names` (count of them); its index in *out. */
static bool read_choice(scene_parser *p, const cJSON *item, const char *path, const char *const names[], int count,
                        int *out)
{
    char shown[MASKED_MAX + 4];
    if (cJSON_IsString(item))
        for (int i = 0; i < count; i++)
            if (strcmp(item->valuestring, names[i]) == 0)
                return *out = i, true;
    return sl_scene_fail(p, path, SL_ERR_FORMAT, "expected \"%s\", \"%s\" or \"%s\"%s%s%s", names[0], names[1], names[2],
                   cJSON_IsString(item) ? ", got \"" : "", cJSON_IsString(item) ? sl_scene_masked(item->valuestring, 32, shown) : "",
                   cJSON_IsString(item) ? "\"" : "");
}

/* A map: "file.png", or {"file", "srgb", "wrap", "filter", "uv_scale", "uv_offset"}. */
static bool parse_map(scene_parser *p, sl_scene *scene, const cJSON *item, const char *path, sl_map_slot slot,
                      sl_material_map *map)
{
    static const char *const keys[] = {"file", "srgb", "wrap", "filter", "uv_scale", "uv_offset", NULL};
    static const char *const wraps[] = {"repeat", "clamp", "mirror"};
    static const char *const filters[] = {"trilinear", "bilinear", "nearest"};
    *map = (sl_material_map){.set = true, .uv_scale = vec2(1.0f, 1.0f)};
    char file[SL_PATH_MAX], sub[JSON_PATH_MAX];
    bool srgb = MAP_SRGB_DEFAULT[slot];
    if (cJSON_IsString(item)) {
        if (!sl_scene_read_path(p, item, path, file))
            return false;
    } else {
        if (!cJSON_IsObject(item))
            return sl_scene_fail(p, path, SL_ERR_FORMAT, "expected an image path or an object {\"file\": ...}");
        if (!sl_scene_check_keys(p, item, path, keys))
            return false;
        const cJSON *v = sl_scene_member(item, "file");
        sl_scene_join_key(sub, path, "file");
        if (!v)
            return sl_scene_fail(p, path, SL_ERR_FORMAT, "needs \"file\" (an image path)");
        if (!sl_scene_read_path(p, v, sub, file))
            return false;
        if ((v = sl_scene_member(item, "srgb"))) {
            sl_scene_join_key(sub, path, "srgb");
            if (!cJSON_IsBool(v))
                return sl_scene_fail(p, sub, SL_ERR_FORMAT, "expected true or false");
            srgb = cJSON_IsTrue(v);
        }
        int choice;
        if ((v = sl_scene_member(item, "wrap"))) {
            sl_scene_join_key(sub, path, "wrap");
            if (!read_choice(p, v, sub, wraps, 3, &choice))
                return false;
            map->wrap = (sl_map_wrap)choice;
        }
        if ((v = sl_scene_member(item, "filter"))) {
            sl_scene_join_key(sub, path, "filter");
            if (!read_choice(p, v, sub, filters, 3, &choice))
                return false;
            map->filter = (sl_map_filter)choice;
        }
        if ((v = sl_scene_member(item, "uv_scale"))) {
            sl_scene_join_key(sub, path, "uv_scale");
            if (!read_uv_pair(p, v, sub, &map->uv_scale))
                return false;
        }
        if ((v = sl_scene_member(item, "uv_offset"))) {
            sl_scene_join_key(sub, path, "uv_offset");
            if (!read_uv_pair(p, v, sub, &map->uv_offset))
                return false;
        }
    }
    return scene_image(p, scene, file, srgb, path, &map->image);
}

/* glTF's keys (docs/scene-format.md "Metallic-roughness, occlusion, emission"): metallic (with a
 * metallic_roughness_map, 1 when not given), occlusion_strength, emissive. Run after the maps. */
static bool parse_pbr(scene_parser *p, const cJSON *item, const char *path, sl_material *m)
{
    char sub[JSON_PATH_MAX];
    const cJSON *v;
    bool mr_map = m->maps[SL_MAP_METALLIC_ROUGHNESS].set;
    if ((v = sl_scene_member(item, "metallic")) || mr_map) {
        sl_scene_join_key(sub, path, v ? "metallic" : "metallic_roughness_map");
        if (m->brdf != SL_BRDF_GGX)
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "a metallic-roughness material needs \"brdf\": \"ggx\"");
        if (sl_scene_member(item, "ks") || m->maps[SL_MAP_KS].set)
            return sl_scene_fail(p, sub, SL_ERR_FORMAT,
                           "a metallic-roughness material takes its ks from kd (the base colour): no ks or ks_map");
        m->metallic = 1.0f;
        if (v && !sl_scene_read_float(p, v, sub, 0.0, 1.0, &m->metallic))
            return false;
    }
    if ((v = sl_scene_member(item, "occlusion_strength"))) {
        sl_scene_join_key(sub, path, "occlusion_strength");
        if (!sl_scene_read_float(p, v, sub, 0.0, 1.0, &m->occlusion_strength))
            return false;
        if (!m->maps[SL_MAP_OCCLUSION].set)
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "needs an occlusion_map");
    }
    if ((v = sl_scene_member(item, "emissive"))) {
        sl_scene_join_key(sub, path, "emissive");
        if (!sl_scene_read_color(p, v, sub, MAX_EMISSIVE, &m->emissive))
            return false;
    } else if (m->maps[SL_MAP_EMISSIVE].set) {
        m->emissive = vec3s(1.0f); /* the map alone: its texels are the radiance */
    }
    sl_scene_material_finish(m);
    return true;
}

/* A metallic material without per-texel inputs is folded into constant kd and ks (then drawn by
 * the untextured program, as before); `textured` says which program draws it. */
void sl_scene_material_finish(sl_material *m)
{
    if (m->metallic >= 0.0f && !m->maps[SL_MAP_KD].set && !m->maps[SL_MAP_METALLIC_ROUGHNESS].set) {
        vec3 base = m->kd;
        float k = m->metallic;
        m->kd = scale3(base, 1.0f - k);
        m->ks = vec3(mixf(0.04f, base.x, k), mixf(0.04f, base.y, k), mixf(0.04f, base.z, k));
        m->metallic = -1.0f;
    }
    m->textured = sl_material_has_maps(m) || sl_material_extra(m);
}

static bool parse_material(scene_parser *p, sl_scene *scene, const cJSON *item, const char *path, sl_material *m)
{
    static const char *const keys[] = {"kd",        "ks",         "alpha",        "brdf",
                                       "roughness", "kd_map",     "ks_map",       "alpha_map",
                                       "normal_map", "mask_map",  "alpha_cutoff", "metallic",
                                       "metallic_roughness_map", "occlusion_map", "occlusion_strength", "emissive",
                                       "emissive_map", NULL};
    static const char *const brdfs[] = {"phong", "ggx"}; /* sl_brdf's values */
    if (!sl_scene_check_keys(p, item, path, keys))
        return false;
    char sub[JSON_PATH_MAX];
    const cJSON *v;
    if ((v = sl_scene_member(item, "brdf"))) {
        char name[MASKED_MAX + 4];
        sl_scene_join_key(sub, path, "brdf");
        if (!cJSON_IsString(v) || !v->valuestring)
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "expected \"phong\" or \"ggx\"");
        if (strcmp(v->valuestring, brdfs[SL_BRDF_PHONG]) == 0)
            m->brdf = SL_BRDF_PHONG;
        else if (strcmp(v->valuestring, brdfs[SL_BRDF_GGX]) == 0)
            m->brdf = SL_BRDF_GGX;
        else
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "unknown brdf \"%s\": expected \"phong\" or \"ggx\"",
                           sl_scene_masked(v->valuestring, 32, name));
    }
    /* each set has its own parameter: the other's is an error, not ignored */
    if (m->brdf == SL_BRDF_GGX && sl_scene_member(item, "alpha")) {
        sl_scene_join_key(sub, path, "alpha");
        return sl_scene_fail(p, sub, SL_ERR_FORMAT, "alpha is the Phong exponent; a \"ggx\" material takes \"roughness\"");
    }
    if (m->brdf == SL_BRDF_PHONG && sl_scene_member(item, "roughness")) {
        sl_scene_join_key(sub, path, "roughness");
        return sl_scene_fail(p, sub, SL_ERR_FORMAT, "roughness needs \"brdf\": \"ggx\" (a Phong material takes \"alpha\")");
    }
    if ((v = sl_scene_member(item, "roughness"))) {
        sl_scene_join_key(sub, path, "roughness");
        if (!sl_scene_read_float(p, v, sub, 0.0, MAX_ROUGHNESS, &m->roughness))
            return false;
    }
    if ((v = sl_scene_member(item, "kd"))) {
        sl_scene_join_key(sub, path, "kd");
        if (!sl_scene_read_color(p, v, sub, 1.0, &m->kd))
            return false;
    }
    if ((v = sl_scene_member(item, "ks"))) {
        sl_scene_join_key(sub, path, "ks");
        if (!sl_scene_read_color(p, v, sub, 1.0, &m->ks))
            return false;
    }
    if ((v = sl_scene_member(item, "alpha"))) {
        sl_scene_join_key(sub, path, "alpha");
        if (!sl_scene_read_float(p, v, sub, 0.0, MAX_ALPHA, &m->alpha))
            return false;
    }
    for (int slot = 0; slot < SL_MAP_COUNT; slot++) {
        if (!(v = sl_scene_member(item, sl_scene_map_keys[slot])))
            continue;
        sl_scene_join_key(sub, path, sl_scene_map_keys[slot]);
        if (!parse_map(p, scene, v, sub, (sl_map_slot)slot, &m->maps[slot]))
            return false;
        m->textured = true;
    }
    if (!parse_pbr(p, item, path, m))
        return false;
    /* Coverage for the cutoff: mask_map.r, or kd_map's alpha; a mask alone cuts at glTF's 0.5. */
    m->masked = m->maps[SL_MAP_MASK].set;
    m->alpha_cutoff = 0.5f;
    if ((v = sl_scene_member(item, "alpha_cutoff"))) {
        sl_scene_join_key(sub, path, "alpha_cutoff");
        if (!sl_scene_read_float(p, v, sub, 0.0, 1.0, &m->alpha_cutoff))
            return false;
        if (!m->maps[SL_MAP_MASK].set && !m->maps[SL_MAP_KD].set)
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "needs a mask_map or a kd_map (whose alpha it cuts)");
        m->masked = true;
    }
    return true;
}

sl_material sl_scene_default_material(const char *name)
{
    sl_material m = {.kd = vec3s(0.5f), .ks = vec3s(0.04f), .alpha = 100.0f, .brdf = SL_BRDF_PHONG,
                     .roughness = DEFAULT_ROUGHNESS, .metallic = -1.0f, .occlusion_strength = 1.0f};
    snprintf(m.name, sizeof m.name, "%s", name);
    return m;
}

/* Materials are a map from name to definition; `sorted` gets them ordered by name. The
 * array has room for one more, the implicit default material. */
bool sl_scene_parse_materials(scene_parser *p, const cJSON *item, sl_scene *scene, scene_name_index **sorted)
{
    int n = 0;
    if (item) {
        if (!cJSON_IsObject(item))
            return sl_scene_fail(p, "materials", SL_ERR_FORMAT, "expected an object {\"name\": {\"kd\": ...}, ...}");
        n = cJSON_GetArraySize(item);
    }
    scene->materials = calloc((size_t)n + 1, sizeof *scene->materials);
    *sorted = calloc((size_t)n + 1, sizeof **sorted);
    if (!scene->materials || !*sorted)
        return sl_scene_fail(p, "materials", SL_ERR_MEMORY, "out of memory for %d materials", n);
    if (!item)
        return true;
    for (const cJSON *child = item->child; child; child = child->next) {
        char path[JSON_PATH_MAX];
        sl_scene_join_key(path, "materials", child->string);
        /* A material is an object, so a "comment" string here cannot be mistaken for one. */
        if (strcmp(child->string, "comment") == 0 && sl_scene_comment_ok(child))
            continue;
        size_t len = strlen(child->string);
        if (len == 0 || len >= SL_NAME_MAX)
            return sl_scene_fail(p, path, SL_ERR_RANGE, "a material name must have 1..%d bytes", SL_NAME_MAX - 1);
        if (!sl_scene_check_no_control(p, child->string, path))
            return false;
        sl_material *m = &scene->materials[scene->material_count];
        *m = sl_scene_default_material(child->string);
        if (!parse_material(p, scene, child, path, m))
            return false;
        (*sorted)[scene->material_count] = (scene_name_index){m->name, scene->material_count};
        scene->material_count++;
    }
    qsort(*sorted, (size_t)scene->material_count, sizeof **sorted, compare_names);
    for (int i = 1; i < scene->material_count; i++) {
        if (strcmp((*sorted)[i - 1].name, (*sorted)[i].name) == 0) {
            char path[JSON_PATH_MAX];
            sl_scene_join_key(path, "materials", (*sorted)[i].name);
            return sl_scene_fail(p, path, SL_ERR_FORMAT, "defined twice");
        }
    }
    return true;
}

int sl_scene_find_material(const scene_name_index *sorted, int count, const char *name)
{
    scene_name_index key = {name, -1};
    const scene_name_index *hit = count ? bsearch(&key, sorted, (size_t)count, sizeof key, compare_names) : NULL;
    return hit ? hit->index : -1;
}
