/* scene.c - the scene file (JSON, docs/scene-format.md) turned into an sl_scene.
 *
 * Owns: reading and validating every field of a scene file, filling defaults, resolving
 * paths relative to the scene file, and loading each distinct mesh once. A scene file is
 * typed by hand, so strictness is a feature: unknown and duplicate keys, wrong types,
 * non-finite or out-of-range numbers are errors, and each error names the file and the JSON
 * path of the offending value (`bunny.json: objects[3].material: no material named "gold"`).
 * The parser walks the cJSON tree section by section; every helper takes the JSON path of
 * the value it reads so the message can say where. */
#include "scene_internal.h"

#include "model.h" /* sl_path_is_scene */

#include <cjson/cJSON.h>
#include <float.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/image.h"   /* sl_read_file */
#include "../core/options.h" /* the render settings' defaults and limits */

#define SCENE_MAX_FILE_BYTES ((size_t)16 << 20)
#define JSON_PATH_MAX 256

/* Defaults (docs/scene-format.md lists the same values). Those of the render settings and the
 * environment's intensity, and their limits, are the option table's (core/options.h). */
#define DEFAULT_FOVY 45.0f
#define DEFAULT_NEAR 0.1f
#define DEFAULT_FAR 100.0f
#define DEFAULT_SLICES 64
#define DEFAULT_STACKS 32
#define DEFAULT_MATERIAL_NAME "default"

/* Limits on values that are legal JSON but absurd for a frame. */
#define MAX_ALPHA 1e6
/* GGX roughness is glTF's perceptual roughness, in [0, 1] by definition; default 0.5. */
#define MAX_ROUGHNESS 1.0
#define DEFAULT_ROUGHNESS 0.5f
/* Far/near beyond this leaves a float depth buffer almost no precision. */
#define MAX_DEPTH_RATIO 1e7
/* Up closer than this (sine of the angle) to the view direction gives an unstable basis. */
#define MIN_UP_SINE 1e-3f

typedef struct {
    const char *name;     /* the scene's name in messages */
    const char *base_dir; /* for relative paths; "" = as given */
    sl_error *err;
    scene_model_camera *model_camera; /* the models' first camera, for the default scene; may be NULL */
} parser;

/* A material name and its index, sorted by name for duplicate checks and lookups. */
typedef struct {
    const char *name;
    int index;
} name_index;

/* ---- errors and JSON paths ---- */

static bool fail_at(parser *p, const char *path, sl_error_code code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
static bool fail_at(parser *p, const char *path, sl_error_code code, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (path && path[0])
        return sl_fail(p->err, code, "%s: %s: %s", p->name, path, msg);
    return sl_fail(p->err, code, "%s: %s", p->name, msg);
}

/* Up to `max` (at most 64) bytes of a key or string from the file for a message, each byte that
 * is not printable ASCII shown as '?' and "..." after a longer one, as the .hdr and OBJ
 * readers do: a scene file cannot put escape sequences or broken UTF-8 on a terminal. */
#define MASKED_MAX 64
static const char *masked(const char *s, size_t max, char out[MASKED_MAX + 4])
{
    return sl_error_excerpt(s, max, out, MASKED_MAX + 4);
}

/* A path too long for the buffer (deep nesting, long names) ends in "..." rather than failing. */
static void mark_truncated(char *out, int written)
{
    if (written >= JSON_PATH_MAX)
        memcpy(out + JSON_PATH_MAX - 4, "...", 4);
}

static void join_key(char *out, const char *path, const char *key)
{
    char shown[MASKED_MAX + 4];
    mark_truncated(out, snprintf(out, JSON_PATH_MAX, "%s%s%s", path, path[0] ? "." : "", masked(key, 64, shown)));
}

static void join_index(char *out, const char *path, int i)
{
    mark_truncated(out, snprintf(out, JSON_PATH_MAX, "%s[%d]", path, i));
}


/* ---- typed readers: each checks the JSON type and range of one value ---- */

static const cJSON *member(const cJSON *obj, const char *key)
{
    return cJSON_GetObjectItemCaseSensitive(obj, key);
}

static bool comment_ok(const cJSON *item)
{
    if (cJSON_IsString(item))
        return true;
    if (!cJSON_IsArray(item))
        return false;
    for (const cJSON *line = item->child; line; line = line->next)
        if (!cJSON_IsString(line))
            return false;
    return true;
}

/* `item` must be an object whose keys are all in `allowed` (plus "comment"), none repeated. */
static bool check_keys(parser *p, const cJSON *item, const char *path, const char *const allowed[])
{
    if (!cJSON_IsObject(item))
        return fail_at(p, path, SL_ERR_FORMAT, "expected an object {...}");
    char shown[MASKED_MAX + 4];
    for (const cJSON *child = item->child; child; child = child->next) {
        const char *key = child->string;
        for (const cJSON *prev = item->child; prev != child; prev = prev->next)
            if (strcmp(prev->string, key) == 0)
                return fail_at(p, path, SL_ERR_FORMAT, "duplicate key \"%s\"", masked(key, 64, shown));
        if (strcmp(key, "comment") == 0) {
            if (!comment_ok(child)) {
                char sub[JSON_PATH_MAX];
                join_key(sub, path, key);
                return fail_at(p, sub, SL_ERR_FORMAT, "expected a string or an array of strings");
            }
            continue;
        }
        bool known = false;
        for (int i = 0; allowed[i] && !known; i++)
            known = strcmp(allowed[i], key) == 0;
        if (!known) {
            char list[256] = "";
            size_t used = 0;
            for (int i = 0; allowed[i] && used < sizeof list; i++)
                used += (size_t)snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", allowed[i]);
            return fail_at(p, path[0] ? path : NULL, SL_ERR_FORMAT, "unknown key \"%s\" (expected %s%scomment)",
                           masked(key, 64, shown), list, list[0] ? " or " : "");
        }
    }
    return true;
}

static bool read_number(parser *p, const cJSON *item, const char *path, double *out)
{
    if (!cJSON_IsNumber(item))
        return fail_at(p, path, SL_ERR_FORMAT, "expected a number");
    double x = item->valuedouble;
    /* cJSON turns 1e999 into inf; anything beyond float's range would become inf later. */
    if (!isfinite(x) || fabs(x) > (double)FLT_MAX)
        return fail_at(p, path, SL_ERR_RANGE, "%g is not a finite float", x);
    *out = x;
    return true;
}

/* A float in [lo, hi]. */
static bool read_float(parser *p, const cJSON *item, const char *path, double lo, double hi, float *out)
{
    double x = 0.0;
    if (!read_number(p, item, path, &x))
        return false;
    if (x < lo || x > hi)
        return fail_at(p, path, SL_ERR_RANGE, "%g is outside %g..%g", x, lo, hi);
    *out = (float)x;
    return true;
}

static bool read_int(parser *p, const cJSON *item, const char *path, int lo, int hi, int *out)
{
    double x = 0.0;
    if (!read_number(p, item, path, &x))
        return false;
    if (x != floor(x))
        return fail_at(p, path, SL_ERR_FORMAT, "expected an integer, got %g", x);
    if (x < lo || x > hi)
        return fail_at(p, path, SL_ERR_RANGE, "%g is outside %d..%d", x, lo, hi);
    *out = (int)x;
    return true;
}

/* An array of exactly n finite numbers. */
static bool read_numbers(parser *p, const cJSON *item, const char *path, int n, double *out)
{
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != n) {
        static const char *const shape[] = {"", "", "an array of 2 numbers", "an array of 3 numbers",
                                            "an array of 4 numbers"};
        return fail_at(p, path, SL_ERR_FORMAT, "expected %s", shape[n]);
    }
    int i = 0;
    for (const cJSON *e = item->child; e; e = e->next, i++) {
        char sub[JSON_PATH_MAX];
        join_index(sub, path, i);
        if (!cJSON_IsNumber(e))
            return fail_at(p, path, SL_ERR_FORMAT, "expected an array of %d numbers", n);
        if (!read_number(p, e, sub, &out[i]))
            return false;
    }
    return true;
}

static bool read_vec3(parser *p, const cJSON *item, const char *path, vec3 *out)
{
    double v[3];
    if (!read_numbers(p, item, path, 3, v))
        return false;
    *out = vec3(v[0], v[1], v[2]);
    return true;
}

/* IEC 61966-2-1 sRGB decoding, the exact piecewise curve (not the 2.2 power). */
static double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }

static int hex_digit(char ch)
{
    if (ch >= '0' && ch <= '9')
        return ch - '0';
    if (ch >= 'a' && ch <= 'f')
        return ch - 'a' + 10;
    if (ch >= 'A' && ch <= 'F')
        return ch - 'A' + 10;
    return -1;
}

/* A colour: [r, g, b] linear, a single number (grey, linear) or "#rrggbb" (sRGB). Linear
 * components must lie in [0, hi]. */
static bool read_color(parser *p, const cJSON *item, const char *path, double hi, vec3 *out)
{
    if (cJSON_IsString(item)) {
        const char *s = item->valuestring;
        char shown[MASKED_MAX + 4];
        double c[3];
        bool ok = strlen(s) == 7 && s[0] == '#';
        for (int i = 0; ok && i < 3; i++) {
            int h = hex_digit(s[1 + 2 * i]), l = hex_digit(s[2 + 2 * i]);
            ok = h >= 0 && l >= 0;
            c[i] = srgb_to_linear((double)(16 * h + l) / 255.0);
        }
        if (!ok)
            return fail_at(p, path, SL_ERR_FORMAT, "expected an sRGB colour \"#rrggbb\", got \"%s\"",
                           masked(s, 32, shown));
        *out = vec3(c[0], c[1], c[2]);
        return true;
    }
    if (cJSON_IsNumber(item)) {
        float g;
        if (!read_float(p, item, path, 0.0, hi, &g))
            return false;
        *out = vec3s(g);
        return true;
    }
    if (!cJSON_IsArray(item))
        return fail_at(p, path, SL_ERR_FORMAT,
                       "expected [r, g, b] (linear), a number (grey) or \"#rrggbb\" (sRGB)");
    vec3 v;
    if (!read_vec3(p, item, path, &v))
        return false;
    const float c[3] = {v.x, v.y, v.z};
    for (int i = 0; i < 3; i++) {
        if (c[i] < 0.0f || (double)c[i] > hi) {
            char sub[JSON_PATH_MAX];
            join_index(sub, path, i);
            return fail_at(p, sub, SL_ERR_RANGE, "%g is outside 0..%g", (double)c[i], hi);
        }
    }
    *out = v;
    return true;
}

/* A name or a path holds no control character (U+0001..U+001F, U+007F; U+0000 is refused
 * for every string, check_json): messages and `info` print them, and a file name with one is
 * surely a mistake. */
static bool check_no_control(parser *p, const char *s, const char *path)
{
    char shown[MASKED_MAX + 4];
    for (size_t i = 0; s[i]; i++)
        if ((unsigned char)s[i] < 32 || s[i] == 127)
            return fail_at(p, path, SL_ERR_FORMAT,
                           "\"%s\" holds a control character (byte 0x%02x at %zu): not allowed in names and paths",
                           masked(s, 64, shown), (unsigned)(unsigned char)s[i], i);
    return true;
}

static bool read_string(parser *p, const cJSON *item, const char *path, char *out, size_t cap)
{
    if (!cJSON_IsString(item))
        return fail_at(p, path, SL_ERR_FORMAT, "expected a string");
    size_t n = strlen(item->valuestring);
    if (n == 0)
        return fail_at(p, path, SL_ERR_FORMAT, "expected a non-empty string");
    if (n >= cap)
        return fail_at(p, path, SL_ERR_RANGE, "%zu bytes is longer than the %zu allowed", n, cap - 1);
    if (!check_no_control(p, item->valuestring, path))
        return false;
    memcpy(out, item->valuestring, n + 1);
    return true;
}

/* A file path from the scene, resolved relative to the scene file's folder. */
static bool read_path(parser *p, const cJSON *item, const char *path, char out[SL_PATH_MAX])
{
    char rel[SL_PATH_MAX];
    if (!read_string(p, item, path, rel, sizeof rel))
        return false;
    const char *dir = p->base_dir;
    int n;
    if (rel[0] == '/' || !dir[0])
        n = snprintf(out, SL_PATH_MAX, "%s", rel);
    else
        n = snprintf(out, SL_PATH_MAX, "%s%s%s", dir, dir[strlen(dir) - 1] == '/' ? "" : "/", rel);
    if (n < 0 || n >= SL_PATH_MAX)
        return fail_at(p, path, SL_ERR_RANGE, "resolved path is longer than %d bytes", SL_PATH_MAX - 1);
    return true;
}

/* The option `id` at its key(s) in `section`, the object its JSON path ("render.samples") starts
 * with, held to the range the declaration gives scene files, into its field of `options`, marked
 * as given; absent leaves the field as it is. A choice is read by name ("default" where 0 means
 * the default), a flag as true or false. */
static bool read_option(parser *p, const cJSON *section, sl_option_id id, sl_option_values *options)
{
    const sl_option *opt = &sl_options[id];
    void *field = sl_option_field(options, id);
    double lo = sl_option_file_min(opt), hi = sl_option_file_max(opt);
    for (int which = 0; which < 2 && opt->scene[which]; which++) {
        const char *path = opt->scene[which];
        const cJSON *v = member(section, strchr(path, '.') + 1);
        if (!v)
            continue;
        switch (opt->type) {
        case SL_OPTION_FLAG:
            if (!cJSON_IsBool(v))
                return fail_at(p, path, SL_ERR_FORMAT, "expected true or false");
            *(bool *)field = cJSON_IsTrue(v);
            break;
        case SL_OPTION_INT:
        case SL_OPTION_SIZE:
            if (!read_int(p, v, path, (int)lo, (int)hi, (int *)field + which))
                return false;
            break;
        case SL_OPTION_FLOAT: {
            float *f = field;
            if (!read_float(p, v, path, lo, hi, f))
                return false;
            if (opt->file_min_open && !(*f > (float)lo))
                return fail_at(p, path, SL_ERR_RANGE, "%g must be greater than %g (%g < %s <= %g)", (double)*f, lo,
                               lo, opt->name, hi);
            break;
        }
        case SL_OPTION_CHOICE: {
            char name[32], shown[MASKED_MAX + 4], words[96];
            if (!read_string(p, v, path, name, sizeof name))
                return false;
            if (!sl_option_parse(opt, name, (int *)field)) {
                sl_option_choices(opt, words, sizeof words);
                return fail_at(p, path, SL_ERR_RANGE, "unknown %s \"%s\" (expected %s)", opt->name,
                               masked(name, 32, shown), words);
            }
            break;
        }
        }
        options->set |= SL_OPT_BIT(id);
    }
    return true;
}

/* ---- sections ---- */

static bool parse_camera(parser *p, const cJSON *item, sl_camera *cam)
{
    static const char *const keys[] = {"eye", "target", "up", "fovy", "near", "far", NULL};
    *cam = (sl_camera){.eye = vec3(0.0f, -5.0f, 2.0f),
                       .target = vec3(0.0f, 0.0f, 0.0f),
                       .up = vec3(0.0f, 0.0f, 1.0f),
                       .fovy_deg = DEFAULT_FOVY,
                       .znear = DEFAULT_NEAR,
                       .zfar = DEFAULT_FAR};
    if (!item)
        return true;
    if (!check_keys(p, item, "camera", keys))
        return false;
    const cJSON *v;
    if ((v = member(item, "eye")) && !read_vec3(p, v, "camera.eye", &cam->eye))
        return false;
    if ((v = member(item, "target")) && !read_vec3(p, v, "camera.target", &cam->target))
        return false;
    if ((v = member(item, "up")) && !read_vec3(p, v, "camera.up", &cam->up))
        return false;
    if ((v = member(item, "fovy"))) {
        if (!read_float(p, v, "camera.fovy", 0.0, 180.0, &cam->fovy_deg))
            return false;
        if (cam->fovy_deg <= 0.0f || cam->fovy_deg >= 180.0f)
            return fail_at(p, "camera.fovy", SL_ERR_RANGE, "%g is outside (0, 180) degrees, exclusive",
                           (double)cam->fovy_deg);
    }
    /* near and far: any finite value here; their relations are checked below. */
    const double big = (double)FLT_MAX;
    if ((v = member(item, "near")) && !read_float(p, v, "camera.near", -big, big, &cam->znear))
        return false;
    if ((v = member(item, "far")) && !read_float(p, v, "camera.far", -big, big, &cam->zfar))
        return false;
    if (!(cam->znear > 0.0f))
        return fail_at(p, "camera.near", SL_ERR_RANGE, "%g must be greater than 0", (double)cam->znear);
    if (!(cam->zfar > cam->znear))
        return fail_at(p, "camera.far", SL_ERR_RANGE, "%g must be greater than near (%g)", (double)cam->zfar,
                       (double)cam->znear);
    if ((double)cam->zfar / (double)cam->znear > MAX_DEPTH_RATIO)
        return fail_at(p, "camera.far", SL_ERR_RANGE,
                       "far/near = %g exceeds %g; the depth buffer would lose all precision",
                       (double)cam->zfar / (double)cam->znear, MAX_DEPTH_RATIO);
    vec3 f, u;
    if (!sl_scene_safe_normalize(sub3(cam->target, cam->eye), &f))
        return fail_at(p, "camera.target", SL_ERR_RANGE,
                       "equals camera.eye (%g, %g, %g); the view direction is undefined", (double)cam->eye.x,
                       (double)cam->eye.y, (double)cam->eye.z);
    if (!sl_scene_safe_normalize(cam->up, &u))
        return fail_at(p, "camera.up", SL_ERR_RANGE, "must not be the zero vector");
    if (length3(cross(f, u)) < MIN_UP_SINE)
        return fail_at(p, "camera.up", SL_ERR_RANGE,
                       "(%g, %g, %g) is parallel to the view direction (target - eye); pick an up across it",
                       (double)cam->up.x, (double)cam->up.y, (double)cam->up.z);
    return true;
}

/* Degrees reduced into (-360, 360) in double, so huge-but-finite angles keep their meaning. */
static float reduce_degrees(double deg) { return (float)fmod(deg, 360.0); }

static bool parse_environment(parser *p, const cJSON *item, sl_environment_desc *env, sl_option_values *options)
{
    static const char *const keys[] = {"hdr", "irradiance", "intensity", "rotation", NULL};
    *env = (sl_environment_desc){0};
    if (!item)
        return true;
    if (cJSON_IsString(item)) /* shorthand: "environment": "envmaps/studio.hdr" */
        return read_path(p, item, "environment", env->hdr_path);
    if (!cJSON_IsObject(item))
        return fail_at(p, "environment", SL_ERR_FORMAT, "expected an object {\"hdr\": ...} or an .hdr path");
    if (!check_keys(p, item, "environment", keys))
        return false;
    const cJSON *v = member(item, "hdr");
    if (!v)
        return fail_at(p, "environment", SL_ERR_FORMAT, "missing \"hdr\" (the environment's .hdr image)");
    if (!read_path(p, v, "environment.hdr", env->hdr_path))
        return false;
    if ((v = member(item, "irradiance")) && !read_path(p, v, "environment.irradiance", env->irradiance_path))
        return false;
    if (!read_option(p, item, SL_OPT_ENV_INTENSITY, options))
        return false;
    double deg;
    if ((v = member(item, "rotation"))) {
        if (!read_number(p, v, "environment.rotation", &deg))
            return false;
        env->rotation_deg = reduce_degrees(deg);
    }
    return true;
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(((const name_index *)a)->name, ((const name_index *)b)->name);
}

/* ---- texture maps (docs/scene-format.md "Texture maps") ---- */

static const char *const MAP_KEYS[SL_MAP_COUNT] = {"kd_map",   "ks_map",   "alpha_map",
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
static bool scene_image(parser *p, sl_scene *scene, const char *file, bool srgb, const char *path, int *index)
{
    for (int i = 0; i < scene->image_count; i++) {
        if (scene->images[i].srgb == srgb && strcmp(scene->images[i].path, file) == 0) {
            *index = i;
            return true;
        }
    }
    if (scene->image_count == SL_SCENE_MAX_IMAGES)
        return fail_at(p, path, SL_ERR_RANGE, "more than %d distinct image files in one scene", SL_SCENE_MAX_IMAGES);
    if (!scene->images && !(scene->images = calloc(SL_SCENE_MAX_IMAGES, sizeof *scene->images)))
        return fail_at(p, path, SL_ERR_MEMORY, "out of memory for the image table");
    sl_scene_image *img = &scene->images[scene->image_count];
    snprintf(img->path, sizeof img->path, "%s", file);
    img->srgb = srgb;
    _Static_assert(sizeof img->used_by == JSON_PATH_MAX, "a JSON path fits in used_by");
    memcpy(img->used_by, path, strlen(path) + 1);
    *index = scene->image_count++;
    return true;
}

static bool read_uv_pair(parser *p, const cJSON *item, const char *path, vec2 *out)
{
    double v[2];
    if (!read_numbers(p, item, path, 2, v))
        return false;
    for (int i = 0; i < 2; i++)
        if (fabs(v[i]) > MAX_UV_TRANSFORM)
            return fail_at(p, path, SL_ERR_RANGE, "%g is outside -%g..%g", v[i], MAX_UV_TRANSFORM, MAX_UV_TRANSFORM);
    *out = vec2(v[0], v[1]);
    return true;
}

/* One enumerated string among `names` (count of them); its index in *out. */
static bool read_choice(parser *p, const cJSON *item, const char *path, const char *const names[], int count,
                        int *out)
{
    char shown[MASKED_MAX + 4];
    if (cJSON_IsString(item))
        for (int i = 0; i < count; i++)
            if (strcmp(item->valuestring, names[i]) == 0)
                return *out = i, true;
    return fail_at(p, path, SL_ERR_FORMAT, "expected \"%s\", \"%s\" or \"%s\"%s%s%s", names[0], names[1], names[2],
                   cJSON_IsString(item) ? ", got \"" : "", cJSON_IsString(item) ? masked(item->valuestring, 32, shown) : "",
                   cJSON_IsString(item) ? "\"" : "");
}

/* A map: "file.png", or {"file", "srgb", "wrap", "filter", "uv_scale", "uv_offset"}. */
static bool parse_map(parser *p, sl_scene *scene, const cJSON *item, const char *path, sl_map_slot slot,
                      sl_material_map *map)
{
    static const char *const keys[] = {"file", "srgb", "wrap", "filter", "uv_scale", "uv_offset", NULL};
    static const char *const wraps[] = {"repeat", "clamp", "mirror"};
    static const char *const filters[] = {"trilinear", "bilinear", "nearest"};
    *map = (sl_material_map){.set = true, .uv_scale = vec2(1.0f, 1.0f)};
    char file[SL_PATH_MAX], sub[JSON_PATH_MAX];
    bool srgb = MAP_SRGB_DEFAULT[slot];
    if (cJSON_IsString(item)) {
        if (!read_path(p, item, path, file))
            return false;
    } else {
        if (!cJSON_IsObject(item))
            return fail_at(p, path, SL_ERR_FORMAT, "expected an image path or an object {\"file\": ...}");
        if (!check_keys(p, item, path, keys))
            return false;
        const cJSON *v = member(item, "file");
        join_key(sub, path, "file");
        if (!v)
            return fail_at(p, path, SL_ERR_FORMAT, "needs \"file\" (an image path)");
        if (!read_path(p, v, sub, file))
            return false;
        if ((v = member(item, "srgb"))) {
            join_key(sub, path, "srgb");
            if (!cJSON_IsBool(v))
                return fail_at(p, sub, SL_ERR_FORMAT, "expected true or false");
            srgb = cJSON_IsTrue(v);
        }
        int choice;
        if ((v = member(item, "wrap"))) {
            join_key(sub, path, "wrap");
            if (!read_choice(p, v, sub, wraps, 3, &choice))
                return false;
            map->wrap = (sl_map_wrap)choice;
        }
        if ((v = member(item, "filter"))) {
            join_key(sub, path, "filter");
            if (!read_choice(p, v, sub, filters, 3, &choice))
                return false;
            map->filter = (sl_map_filter)choice;
        }
        if ((v = member(item, "uv_scale"))) {
            join_key(sub, path, "uv_scale");
            if (!read_uv_pair(p, v, sub, &map->uv_scale))
                return false;
        }
        if ((v = member(item, "uv_offset"))) {
            join_key(sub, path, "uv_offset");
            if (!read_uv_pair(p, v, sub, &map->uv_offset))
                return false;
        }
    }
    return scene_image(p, scene, file, srgb, path, &map->image);
}

/* glTF's keys (docs/scene-format.md "Metallic-roughness, occlusion, emission"): metallic (with a
 * metallic_roughness_map, 1 when not given), occlusion_strength, emissive. Run after the maps. */
static bool parse_pbr(parser *p, const cJSON *item, const char *path, sl_material *m)
{
    char sub[JSON_PATH_MAX];
    const cJSON *v;
    bool mr_map = m->maps[SL_MAP_METALLIC_ROUGHNESS].set;
    if ((v = member(item, "metallic")) || mr_map) {
        join_key(sub, path, v ? "metallic" : "metallic_roughness_map");
        if (m->brdf != SL_BRDF_GGX)
            return fail_at(p, sub, SL_ERR_FORMAT, "a metallic-roughness material needs \"brdf\": \"ggx\"");
        if (member(item, "ks") || m->maps[SL_MAP_KS].set)
            return fail_at(p, sub, SL_ERR_FORMAT,
                           "a metallic-roughness material takes its ks from kd (the base colour): no ks or ks_map");
        m->metallic = 1.0f;
        if (v && !read_float(p, v, sub, 0.0, 1.0, &m->metallic))
            return false;
    }
    if ((v = member(item, "occlusion_strength"))) {
        join_key(sub, path, "occlusion_strength");
        if (!read_float(p, v, sub, 0.0, 1.0, &m->occlusion_strength))
            return false;
        if (!m->maps[SL_MAP_OCCLUSION].set)
            return fail_at(p, sub, SL_ERR_FORMAT, "needs an occlusion_map");
    }
    if ((v = member(item, "emissive"))) {
        join_key(sub, path, "emissive");
        if (!read_color(p, v, sub, MAX_EMISSIVE, &m->emissive))
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

static bool parse_material(parser *p, sl_scene *scene, const cJSON *item, const char *path, sl_material *m)
{
    static const char *const keys[] = {"kd",        "ks",         "alpha",        "brdf",
                                       "roughness", "kd_map",     "ks_map",       "alpha_map",
                                       "normal_map", "mask_map",  "alpha_cutoff", "metallic",
                                       "metallic_roughness_map", "occlusion_map", "occlusion_strength", "emissive",
                                       "emissive_map", NULL};
    static const char *const brdfs[] = {"phong", "ggx"}; /* sl_brdf's values */
    if (!check_keys(p, item, path, keys))
        return false;
    char sub[JSON_PATH_MAX];
    const cJSON *v;
    if ((v = member(item, "brdf"))) {
        char name[MASKED_MAX + 4];
        join_key(sub, path, "brdf");
        if (!cJSON_IsString(v) || !v->valuestring)
            return fail_at(p, sub, SL_ERR_FORMAT, "expected \"phong\" or \"ggx\"");
        if (strcmp(v->valuestring, brdfs[SL_BRDF_PHONG]) == 0)
            m->brdf = SL_BRDF_PHONG;
        else if (strcmp(v->valuestring, brdfs[SL_BRDF_GGX]) == 0)
            m->brdf = SL_BRDF_GGX;
        else
            return fail_at(p, sub, SL_ERR_FORMAT, "unknown brdf \"%s\": expected \"phong\" or \"ggx\"",
                           masked(v->valuestring, 32, name));
    }
    /* each set has its own parameter: the other's is an error, not ignored */
    if (m->brdf == SL_BRDF_GGX && member(item, "alpha")) {
        join_key(sub, path, "alpha");
        return fail_at(p, sub, SL_ERR_FORMAT, "alpha is the Phong exponent; a \"ggx\" material takes \"roughness\"");
    }
    if (m->brdf == SL_BRDF_PHONG && member(item, "roughness")) {
        join_key(sub, path, "roughness");
        return fail_at(p, sub, SL_ERR_FORMAT, "roughness needs \"brdf\": \"ggx\" (a Phong material takes \"alpha\")");
    }
    if ((v = member(item, "roughness"))) {
        join_key(sub, path, "roughness");
        if (!read_float(p, v, sub, 0.0, MAX_ROUGHNESS, &m->roughness))
            return false;
    }
    if ((v = member(item, "kd"))) {
        join_key(sub, path, "kd");
        if (!read_color(p, v, sub, 1.0, &m->kd))
            return false;
    }
    if ((v = member(item, "ks"))) {
        join_key(sub, path, "ks");
        if (!read_color(p, v, sub, 1.0, &m->ks))
            return false;
    }
    if ((v = member(item, "alpha"))) {
        join_key(sub, path, "alpha");
        if (!read_float(p, v, sub, 0.0, MAX_ALPHA, &m->alpha))
            return false;
    }
    for (int slot = 0; slot < SL_MAP_COUNT; slot++) {
        if (!(v = member(item, MAP_KEYS[slot])))
            continue;
        join_key(sub, path, MAP_KEYS[slot]);
        if (!parse_map(p, scene, v, sub, (sl_map_slot)slot, &m->maps[slot]))
            return false;
        m->textured = true;
    }
    if (!parse_pbr(p, item, path, m))
        return false;
    /* Coverage for the cutoff: mask_map.r, or kd_map's alpha; a mask alone cuts at glTF's 0.5. */
    m->masked = m->maps[SL_MAP_MASK].set;
    m->alpha_cutoff = 0.5f;
    if ((v = member(item, "alpha_cutoff"))) {
        join_key(sub, path, "alpha_cutoff");
        if (!read_float(p, v, sub, 0.0, 1.0, &m->alpha_cutoff))
            return false;
        if (!m->maps[SL_MAP_MASK].set && !m->maps[SL_MAP_KD].set)
            return fail_at(p, sub, SL_ERR_FORMAT, "needs a mask_map or a kd_map (whose alpha it cuts)");
        m->masked = true;
    }
    return true;
}

static sl_material default_material(const char *name)
{
    sl_material m = {.kd = vec3s(0.5f), .ks = vec3s(0.04f), .alpha = 100.0f, .brdf = SL_BRDF_PHONG,
                     .roughness = DEFAULT_ROUGHNESS, .metallic = -1.0f, .occlusion_strength = 1.0f};
    snprintf(m.name, sizeof m.name, "%s", name);
    return m;
}

/* Materials are a map from name to definition; `sorted` gets them ordered by name. The
 * array has room for one more, the implicit default material. */
static bool parse_materials(parser *p, const cJSON *item, sl_scene *scene, name_index **sorted)
{
    int n = 0;
    if (item) {
        if (!cJSON_IsObject(item))
            return fail_at(p, "materials", SL_ERR_FORMAT, "expected an object {\"name\": {\"kd\": ...}, ...}");
        n = cJSON_GetArraySize(item);
    }
    scene->materials = calloc((size_t)n + 1, sizeof *scene->materials);
    *sorted = calloc((size_t)n + 1, sizeof **sorted);
    if (!scene->materials || !*sorted)
        return fail_at(p, "materials", SL_ERR_MEMORY, "out of memory for %d materials", n);
    if (!item)
        return true;
    for (const cJSON *child = item->child; child; child = child->next) {
        char path[JSON_PATH_MAX];
        join_key(path, "materials", child->string);
        /* A material is an object, so a "comment" string here cannot be mistaken for one. */
        if (strcmp(child->string, "comment") == 0 && comment_ok(child))
            continue;
        size_t len = strlen(child->string);
        if (len == 0 || len >= SL_NAME_MAX)
            return fail_at(p, path, SL_ERR_RANGE, "a material name must have 1..%d bytes", SL_NAME_MAX - 1);
        if (!check_no_control(p, child->string, path))
            return false;
        sl_material *m = &scene->materials[scene->material_count];
        *m = default_material(child->string);
        if (!parse_material(p, scene, child, path, m))
            return false;
        (*sorted)[scene->material_count] = (name_index){m->name, scene->material_count};
        scene->material_count++;
    }
    qsort(*sorted, (size_t)scene->material_count, sizeof **sorted, compare_names);
    for (int i = 1; i < scene->material_count; i++) {
        if (strcmp((*sorted)[i - 1].name, (*sorted)[i].name) == 0) {
            char path[JSON_PATH_MAX];
            join_key(path, "materials", (*sorted)[i].name);
            return fail_at(p, path, SL_ERR_FORMAT, "defined twice");
        }
    }
    return true;
}

static int find_material(const name_index *sorted, int count, const char *name)
{
    name_index key = {name, -1};
    const name_index *hit = count ? bsearch(&key, sorted, (size_t)count, sizeof key, compare_names) : NULL;
    return hit ? hit->index : -1;
}

/* "rotate": [ax, ay, az, degrees] or a list of those; the first listed is applied first. */
static bool parse_rotate(parser *p, const cJSON *item, const char *path, mat4 *r)
{
    *r = mat4_identity();
    bool list = cJSON_IsArray(item) && item->child && cJSON_IsArray(item->child);
    int i = 0;
    for (const cJSON *e = list ? item->child : item; e; e = list ? e->next : NULL, i++) {
        char sub[JSON_PATH_MAX];
        if (list)
            join_index(sub, path, i);
        else
            snprintf(sub, sizeof sub, "%s", path);
        double v[4];
        if (!cJSON_IsArray(e) || cJSON_GetArraySize(e) != 4)
            return fail_at(p, sub, SL_ERR_FORMAT, "expected [ax, ay, az, degrees] or a list of them");
        if (!read_numbers(p, e, sub, 4, v))
            return false;
        vec3 axis;
        if (!sl_scene_safe_normalize(vec3(v[0], v[1], v[2]), &axis))
            return fail_at(p, sub, SL_ERR_RANGE, "the rotation axis must not be the zero vector");
        float angle = (float)(fmod(v[3], 360.0) * (3.14159265358979323846 / 180.0));
        *r = mat4_mul(mat4_rotate(axis, angle), *r);
    }
    return true;
}

/* Object -> world = T * R * S: scale about the origin, then rotate, then translate. */
static bool parse_transform(parser *p, const cJSON *item, const char *path, mat4 *model)
{
    static const char *const keys[] = {"translate", "rotate", "scale", NULL};
    *model = mat4_identity();
    if (!item)
        return true;
    if (!check_keys(p, item, path, keys))
        return false;
    char sub[JSON_PATH_MAX];
    vec3 t = vec3s(0.0f), s = vec3s(1.0f);
    mat4 r = mat4_identity();
    const cJSON *v;
    if ((v = member(item, "translate"))) {
        join_key(sub, path, "translate");
        if (!read_vec3(p, v, sub, &t))
            return false;
    }
    if ((v = member(item, "rotate"))) {
        join_key(sub, path, "rotate");
        if (!parse_rotate(p, v, sub, &r))
            return false;
    }
    if ((v = member(item, "scale"))) {
        join_key(sub, path, "scale");
        if (cJSON_IsNumber(v)) {
            double x;
            if (!read_number(p, v, sub, &x))
                return false;
            s = vec3s((float)x);
        } else if (!cJSON_IsArray(v)) {
            return fail_at(p, sub, SL_ERR_FORMAT, "expected a number or an array of 3 numbers");
        } else if (!read_vec3(p, v, sub, &s)) {
            return false;
        }
        /* Negative scales would mirror the mesh and turn its front faces into back faces. */
        const float c[3] = {s.x, s.y, s.z};
        for (int i = 0; i < 3; i++)
            if (!(c[i] >= 1e-6f && c[i] <= 1e6f))
                return fail_at(p, sub, SL_ERR_RANGE, "%g is outside 1e-06..1e+06 (positive; no mirroring)",
                               (double)c[i]);
    }
    *model = mat4_mul(mat4_translate(t), mat4_mul(r, mat4_scale(s)));
    return true;
}

static bool same_source(const sl_mesh_source *a, const sl_mesh_source *b)
{
    return a->kind == b->kind && a->slices == b->slices && a->stacks == b->stacks && strcmp(a->path, b->path) == 0;
}

/* The distinct mesh sources seen so far, hashed (open addressing, at most half full: sized
 * for every object naming its own source), so that finding an object's mesh costs O(1), not
 * a scan of every mesh before it (which takes 18.6 s for 80,000 objects naming distinct OBJ
 * files). */
typedef struct {
    int *slots; /* mesh index + 1; 0 = empty */
    size_t mask;
} source_map;

/* FNV-1a over the kind, the tessellation and the path. */
static uint32_t source_hash(const sl_mesh_source *s)
{
    uint32_t h = 2166136261u;
    const int head[3] = {(int)s->kind, s->slices, s->stacks};
    const unsigned char *b = (const unsigned char *)head;
    for (size_t i = 0; i < sizeof head; i++)
        h = (h ^ b[i]) * 16777619u;
    for (const unsigned char *c = (const unsigned char *)s->path; *c; c++)
        h = (h ^ *c) * 16777619u;
    return h;
}

static bool source_map_init(source_map *map, size_t sources)
{
    size_t size = 16;
    while (size < 2 * sources)
        size *= 2;
    map->slots = calloc(size, sizeof *map->slots);
    map->mask = size - 1;
    return map->slots != NULL;
}

/* The mesh of `src`: an earlier one with the same source, or a new one (first used by object
 * `object`). The map has room for every object's source. */
static int source_mesh(source_map *map, sl_scene *scene, int *first_user, const sl_mesh_source *src, int object)
{
    size_t s = source_hash(src) & map->mask;
    for (; map->slots[s]; s = (s + 1) & map->mask)
        if (same_source(&scene->mesh_sources[map->slots[s] - 1], src))
            return map->slots[s] - 1;
    int mesh = scene->mesh_count++;
    scene->mesh_sources[mesh] = *src;
    first_user[mesh] = object;
    map->slots[s] = mesh + 1;
    return mesh;
}

/* The object's default name: the OBJ file's base name without extension, or the shape. */
static void default_object_name(char out[SL_NAME_MAX], const char *mesh_text, const char *shape)
{
    if (shape) {
        snprintf(out, SL_NAME_MAX, "%s", shape);
        return;
    }
    const char *base = strrchr(mesh_text, '/');
    base = base ? base + 1 : mesh_text;
    size_t n = strcspn(base, ".");
    if (n == 0)
        n = strlen(base);
    snprintf(out, SL_NAME_MAX, "%.*s", (int)(n < SL_NAME_MAX - 1 ? n : SL_NAME_MAX - 1), base);
}

static bool parse_object(parser *p, const cJSON *item, const char *path, sl_scene *scene,
                         const name_index *sorted, int named_materials, source_map *sources, int *first_user,
                         sl_object *obj, bool *material_given)
{
    static const char *const keys[] = {"name", "mesh", "shape", "model", "slices", "stacks", "material", "transform",
                                       NULL};
    static const char *const shapes[] = {"sphere", "plane", "box"};
    static const sl_mesh_kind kinds[] = {SL_MESH_SPHERE, SL_MESH_PLANE, SL_MESH_BOX};
    if (!check_keys(p, item, path, keys))
        return false;
    char sub[JSON_PATH_MAX], shown[MASKED_MAX + 4];
    const cJSON *mesh = member(item, "mesh"), *shape = member(item, "shape"), *model = member(item, "model");
    if (!!mesh + !!shape + !!model > 1)
        return fail_at(p, path, SL_ERR_FORMAT, "has more than one of \"mesh\", \"shape\" and \"model\"; give one");
    if (!mesh && !shape && !model)
        return fail_at(p, path, SL_ERR_FORMAT,
                       "needs \"mesh\" (an .obj path), \"shape\" (\"sphere\", \"plane\" or \"box\") or \"model\" "
                       "(a glTF, OBJ, ... file)");
    sl_mesh_source src = {.kind = SL_MESH_OBJ};
    const char *shape_name = NULL;
    if (model) {
        join_key(sub, path, "model");
        src.kind = SL_MESH_MODEL;
        if (!read_path(p, model, sub, src.path))
            return false;
        mesh = model; /* the object's default name comes from the file's */
    } else if (mesh) {
        join_key(sub, path, "mesh");
        if (!read_path(p, mesh, sub, src.path))
            return false;
    } else {
        join_key(sub, path, "shape");
        if (!cJSON_IsString(shape))
            return fail_at(p, sub, SL_ERR_FORMAT, "expected \"sphere\", \"plane\" or \"box\"");
        for (int i = 0; i < 3 && !shape_name; i++)
            if (strcmp(shape->valuestring, shapes[i]) == 0)
                shape_name = shapes[i], src.kind = kinds[i];
        if (!shape_name)
            return fail_at(p, sub, SL_ERR_FORMAT, "unknown shape \"%s\" (expected sphere, plane or box)",
                           masked(shape->valuestring, 32, shown));
    }
    const cJSON *v;
    if (src.kind == SL_MESH_SPHERE) {
        src.slices = DEFAULT_SLICES;
        src.stacks = DEFAULT_STACKS;
    }
    static const char *const tess[2] = {"slices", "stacks"};
    for (int i = 0; i < 2; i++) {
        if (!(v = member(item, tess[i])))
            continue;
        join_key(sub, path, tess[i]);
        if (src.kind != SL_MESH_SPHERE)
            return fail_at(p, sub, SL_ERR_FORMAT, "only a sphere has %s", tess[i]);
        bool ok = i == 0 ? read_int(p, v, sub, 3, SCENE_SPHERE_MAX_SLICES, &src.slices)
                         : read_int(p, v, sub, 2, SCENE_SPHERE_MAX_STACKS, &src.stacks);
        if (!ok)
            return false;
    }

    if ((v = member(item, "name"))) {
        join_key(sub, path, "name");
        if (!read_string(p, v, sub, obj->name, sizeof obj->name))
            return false;
    } else {
        default_object_name(obj->name, mesh ? mesh->valuestring : "", shape_name);
    }

    *material_given = member(item, "material") != NULL;
    if ((v = member(item, "material"))) {
        join_key(sub, path, "material");
        if (!cJSON_IsString(v))
            return fail_at(p, sub, SL_ERR_FORMAT, "expected a material name (a string)");
        obj->material = find_material(sorted, named_materials, v->valuestring);
        if (obj->material < 0)
            return fail_at(p, sub, SL_ERR_FORMAT, "no material named \"%s\"", masked(v->valuestring, 64, shown));
    } else {
        /* No material: the one named "default" if the scene defines it, else a built-in grey. */
        obj->material = find_material(sorted, named_materials, DEFAULT_MATERIAL_NAME);
        if (obj->material < 0) {
            obj->material = named_materials;
            if (scene->material_count == named_materials) {
                scene->materials[named_materials] = default_material(DEFAULT_MATERIAL_NAME);
                scene->material_count++;
            }
        }
    }

    join_key(sub, path, "transform");
    if (!parse_transform(p, member(item, "transform"), sub, &obj->model))
        return false;

    /* One mesh per distinct source. */
    obj->mesh = source_mesh(sources, scene, first_user, &src, (int)(obj - scene->objects));
    return true;
}

static bool parse_lights(parser *p, const cJSON *item, sl_scene *scene)
{
    static const char *const keys[] = {"position", "color", "intensity", NULL};
    if (!item)
        return true;
    if (!cJSON_IsArray(item))
        return fail_at(p, "lights", SL_ERR_FORMAT, "expected an array of lights [{\"position\": ...}, ...]");
    scene->lights = calloc(SL_LIGHTING_MAX_LIGHTS, sizeof *scene->lights);
    if (!scene->lights)
        return fail_at(p, "lights", SL_ERR_MEMORY, "out of memory for %d lights", SL_LIGHTING_MAX_LIGHTS);
    for (const cJSON *e = item->child; e; e = e->next) {
        char path[JSON_PATH_MAX], sub[JSON_PATH_MAX];
        join_index(path, "lights", scene->light_count);
        /* The lighting shader's uniform arrays hold this many; a scene with more would pass
         * `info` and fail only when a frame is lit (even one with point lights off). */
        if (scene->light_count == SL_LIGHTING_MAX_LIGHTS)
            return fail_at(p, path, SL_ERR_RANGE, "at most %d point lights (MAX_LIGHTS of shaders/lighting.frag)",
                           SL_LIGHTING_MAX_LIGHTS);
        if (!check_keys(p, e, path, keys))
            return false;
        sl_point_light *l = &scene->lights[scene->light_count];
        *l = (sl_point_light){.color = vec3s(1.0f), .intensity = 1.0f};
        const cJSON *v = member(e, "position");
        join_key(sub, path, "position");
        if (!v)
            return fail_at(p, path, SL_ERR_FORMAT, "missing \"position\"");
        if (!read_vec3(p, v, sub, &l->position))
            return false;
        join_key(sub, path, "color");
        if ((v = member(e, "color")) && !read_color(p, v, sub, 1e6, &l->color))
            return false;
        join_key(sub, path, "intensity");
        if ((v = member(e, "intensity")) && !read_float(p, v, sub, 0.0, 1e9, &l->intensity))
            return false;
        scene->light_count++;
    }
    return true;
}

/* The "render" object: a key per row of the option declaration whose scene key starts with
 * "render." (core/options.h), each read by read_option. */
static bool parse_render(parser *p, const cJSON *item, sl_option_values *options)
{
    const char *keys[SL_OPT_COUNT + 2];
    int n = 0;
    for (int id = 0; id < SL_OPT_COUNT; id++)
        for (int which = 0; which < 2; which++) {
            const char *path = sl_options[id].scene[which];
            if (path && !strncmp(path, "render.", 7))
                keys[n++] = path + 7;
        }
    keys[n] = NULL;
    if (!item)
        return true;
    if (!check_keys(p, item, "render", keys))
        return false;
    for (int id = 0; id < SL_OPT_COUNT; id++)
        if (sl_options[id].scene[0] && !strncmp(sl_options[id].scene[0], "render.", 7) &&
            !read_option(p, item, (sl_option_id)id, options))
            return false;
    return sl_option_values_check(options, p->name, p->err);
}

/* Build every distinct mesh. Each mesh is capped on its own (scene_internal.h); the scene as
 * a whole is capped too, so that many large meshes cannot add up to an absurd allocation. */
static bool load_meshes_now(parser *p, sl_scene *scene, const int *first_user)
{
    long long total_vertices = 0;
    for (int i = 0; i < scene->mesh_count; i++) {
        const sl_mesh_source *src = &scene->mesh_sources[i];
        sl_mesh *m = &scene->meshes[i];
        bool ok;
        switch (src->kind) {
        case SL_MESH_OBJ:
            ok = sl_mesh_load_obj(src->path, m, p->err) && sl_mesh_validate(m, src->path, p->err);
            break;
        case SL_MESH_SPHERE: ok = sl_mesh_sphere(m, src->slices, src->stacks, p->err); break;
        case SL_MESH_PLANE: ok = sl_mesh_plane(m, p->err); break;
        case SL_MESH_BOX: ok = sl_mesh_box(m, p->err); break;
        case SL_MESH_MODEL: ok = true; break; /* sl_scene_expand_models, below */
        default: ok = sl_fail(p->err, SL_ERR_FORMAT, "unknown mesh kind %d", (int)src->kind); break;
        }
        total_vertices += m->vertex_count;
        if (ok && total_vertices > SCENE_MAX_TOTAL_VERTICES)
            ok = sl_fail(p->err, SL_ERR_RANGE, "the scene's meshes have more than %d vertices in all",
                         SCENE_MAX_TOTAL_VERTICES);
        if (!ok) {
            sl_error_prefix(p->err, "%s: objects[%d].%s: ", p->name, first_user[i],
                            src->kind == SL_MESH_OBJ ? "mesh" : "shape");
            return false;
        }
    }
    return true;
}

/* A material with maps needs texture coordinates on every mesh it is drawn on (the shapes
 * always have them; an OBJ file has them when its faces name vt). */
static bool check_maps_have_uvs(parser *p, const sl_scene *scene)
{
    for (int i = 0; i < scene->object_count; i++) {
        const sl_object *o = &scene->objects[i];
        const sl_material *m = &scene->materials[o->material];
        if (!sl_material_has_maps(m) || scene->meshes[o->mesh].texcoords)
            continue;
        int slot = 0;
        while (!m->maps[slot].set)
            slot++;
        char path[JSON_PATH_MAX];
        join_index(path, "objects", i);
        char shown[MASKED_MAX + 4];
        return fail_at(p, path, SL_ERR_FORMAT,
                       "material \"%s\" has a %s (%s) but the mesh %s has no texture coordinates (no vt on its faces)",
                       masked(m->name, 64, shown), MAP_KEYS[slot], scene->images[m->maps[slot].image].path,
                       scene->mesh_sources[o->mesh].path);
    }
    return true;
}

/* Line and column (1-based) of a byte offset, for JSON syntax errors. */
static void line_column(const char *text, size_t offset, size_t *line, size_t *column)
{
    *line = 1;
    *column = 1;
    for (size_t i = 0; i < offset; i++) {
        if (text[i] == '\n')
            ++*line, *column = 1;
        else
            ++*column;
    }
}

static bool parse_document(parser *p, const cJSON *root, bool load_meshes, sl_scene *scene)
{
    static const char *const keys[] = {"camera", "environment", "materials", "objects", "lights", "render", NULL};
    if (!cJSON_IsObject(root))
        return fail_at(p, NULL, SL_ERR_FORMAT, "expected a JSON object {...} at the top level");
    if (!check_keys(p, root, "", keys))
        return false;
    name_index *sorted = NULL;
    int *first_user = NULL;
    bool *material_given = NULL;
    source_map sources = {0};
    bool ok = parse_camera(p, member(root, "camera"), &scene->camera) &&
              parse_environment(p, member(root, "environment"), &scene->environment, &scene->options) &&
              parse_render(p, member(root, "render"), &scene->options) &&
              parse_materials(p, member(root, "materials"), scene, &sorted);
    const cJSON *objects = member(root, "objects");
    if (ok && objects && !cJSON_IsArray(objects))
        ok = fail_at(p, "objects", SL_ERR_FORMAT, "expected an array of objects [{\"shape\": ...}, ...]");
    if (ok) {
        size_t n = (size_t)(objects ? cJSON_GetArraySize(objects) : 0);
        scene->objects = calloc(n + 1, sizeof *scene->objects);
        scene->mesh_sources = calloc(n + 1, sizeof *scene->mesh_sources);
        first_user = calloc(n + 1, sizeof *first_user);
        material_given = calloc(n + 1, sizeof *material_given);
        if (!scene->objects || !scene->mesh_sources || !first_user || !material_given || !source_map_init(&sources, n))
            ok = fail_at(p, "objects", SL_ERR_MEMORY, "out of memory for %zu objects", n);
    }
    int named_materials = scene->material_count;
    for (const cJSON *e = objects && ok ? objects->child : NULL; e && ok; e = e->next) {
        char path[JSON_PATH_MAX];
        join_index(path, "objects", scene->object_count);
        sl_object *obj = &scene->objects[scene->object_count];
        ok = parse_object(p, e, path, scene, sorted, named_materials, &sources, first_user, obj,
                          &material_given[scene->object_count]);
        if (ok)
            scene->object_count++;
    }
    ok = ok && parse_lights(p, member(root, "lights"), scene);
    if (ok) {
        scene->meshes = calloc((size_t)scene->mesh_count + 1, sizeof *scene->meshes);
        if (!scene->meshes)
            ok = fail_at(p, "objects", SL_ERR_MEMORY, "out of memory for %d meshes", scene->mesh_count);
    }
    if (ok && load_meshes)
        ok = load_meshes_now(p, scene, first_user) &&
             sl_scene_expand_models(scene, material_given, first_user, p->name, p->model_camera, p->err) &&
             check_maps_have_uvs(p, scene);
    free(sorted);
    free(first_user);
    free(material_given);
    free(sources.slots);
    return ok;
}

/* ---- what cJSON does not say: nesting past its limit, and U+0000 inside a string ---- */

/* cJSON refuses arrays and objects nested deeper than this (CJSON_NESTING_LIMIT, 1000 in the
 * packaged library) without a reason; scan_json says so, and where. */
#define JSON_MAX_DEPTH CJSON_NESTING_LIMIT

/* The JSON path of the place scan_json has reached. Bytes past the buffer are counted, not
 * stored, so that leaving a deep level restores the path exactly; a path that long is shown
 * ending in "..." (as mark_truncated does). */
typedef struct {
    char buf[JSON_PATH_MAX];
    size_t len;
} json_path;

static void path_put(json_path *jp, const char *s, size_t n)
{
    for (size_t i = 0; i < n; i++, jp->len++)
        if (jp->len < JSON_PATH_MAX - 1)
            jp->buf[jp->len] = s[i];
}

/* "t.json:3:14: objects[0].name" (no path at the top level), for the message at `offset`. */
static const char *json_where(const parser *p, const char *text, size_t offset, json_path *jp,
                              char out[JSON_PATH_MAX + 128])
{
    size_t line, column;
    line_column(text, offset, &line, &column);
    if (jp->len < JSON_PATH_MAX - 1)
        jp->buf[jp->len] = '\0';
    else
        memcpy(jp->buf + JSON_PATH_MAX - 4, "...", 4);
    snprintf(out, JSON_PATH_MAX + 128, "%.100s:%zu:%zu%s%s", p->name, line, column, jp->len ? ": " : "",
             jp->len ? jp->buf : "");
    return out;
}

typedef struct {
    size_t base;     /* path length of the array or object itself */
    long index;      /* array: the element being read */
    bool object;     /* an object: its strings alternate key, value */
    bool expect_key; /* object: the next string is a key */
} json_frame;

/* Walks the JSON text [0, end), which cJSON has read as valid JSON as far as it goes, keeping
 * the path of where it is, and stops at the first of: an array or object opened deeper than
 * JSON_MAX_DEPTH (when `depth`; cJSON's own error is only "invalid JSON"), or a string, key or
 * value, holding the escape \u0000 (when `nul`), which cJSON decodes to a NUL byte that
 * silently ends the string ("na\u0000me" is read as the key "na"). False with the error
 * (line, column and path); true when neither is found. */
static bool scan_json(parser *p, const char *text, size_t end, bool depth, bool nul)
{
    json_frame *frames = calloc(JSON_MAX_DEPTH + 1, sizeof *frames);
    if (!frames)
        return sl_fail(p->err, SL_ERR_MEMORY, "%s: out of memory for the JSON checks", p->name);
    json_path jp = {.len = 0};
    int level = 0;
    bool ok = true;
    char where[JSON_PATH_MAX + 128], shown[MASKED_MAX + 4], number[24];
    for (size_t i = 0; i < end && ok; i++) {
        json_frame *top = level > 0 ? &frames[level - 1] : NULL;
        switch (text[i]) {
        case '{':
        case '[':
            if (level == JSON_MAX_DEPTH) {
                if (depth)
                    ok = sl_fail(p->err, SL_ERR_FORMAT,
                                 "%s: arrays and objects nested deeper than %d levels (the JSON parser's limit)",
                                 json_where(p, text, i, &jp, where), JSON_MAX_DEPTH);
                i = end; /* cJSON read no further */
                break;
            }
            frames[level++] = (json_frame){.base = jp.len, .object = text[i] == '{', .expect_key = text[i] == '{'};
            if (text[i] == '[')
                path_put(&jp, "[0]", 3);
            break;
        case '}':
        case ']':
            if (top) {
                jp.len = top->base;
                level--;
            }
            break;
        case ',':
            if (top) {
                jp.len = top->base;
                top->expect_key = top->object;
                if (!top->object)
                    path_put(&jp, number, (size_t)snprintf(number, sizeof number, "[%ld]", ++top->index));
            }
            break;
        case '"': {
            /* The string as written (escapes not decoded), and its first \u0000. */
            size_t start = i + 1, j = start, zero = 0;
            bool has_zero = false;
            for (; j < end && text[j] != '"'; j++) {
                if (text[j] != '\\')
                    continue;
                if (!has_zero && j + 5 < end && text[j + 1] == 'u' && memcmp(text + j + 2, "0000", 4) == 0)
                    has_zero = true, zero = j;
                j++; /* the escaped character: \" and \\ neither end nor start anything */
            }
            if (j > end) /* a backslash as the last byte: the string ends with the text */
                j = end;
            char raw[MASKED_MAX + 2];
            size_t n = j - start <= MASKED_MAX ? j - start : MASKED_MAX + 1; /* masked() adds "..." */
            memcpy(raw, text + start, n);
            raw[n] = '\0';
            masked(raw, MASKED_MAX, shown);
            bool key = top && top->object && top->expect_key;
            if (key) { /* the path of the object; its value's path adds the key */
                jp.len = top->base;
                top->expect_key = false;
            }
            if (has_zero && nul) {
                ok = key ? sl_fail(p->err, SL_ERR_FORMAT,
                                   "%s: the key \"%s\" holds \\u0000 (a NUL character), which would cut it short",
                                   json_where(p, text, zero, &jp, where), shown)
                         : sl_fail(p->err, SL_ERR_FORMAT,
                                   "%s: the string \"%s\" holds \\u0000 (a NUL character), which would cut it short",
                                   json_where(p, text, zero, &jp, where), shown);
            }
            if (key) {
                if (top->base > 0)
                    path_put(&jp, ".", 1);
                path_put(&jp, shown, strlen(shown));
            }
            i = j;
            break;
        }
        default: break; /* ':', numbers, true, false, null, white space */
        }
    }
    free(frames);
    return ok;
}

static bool parse_scene(const char *json, size_t size, const char *name, const char *base_dir, bool load_meshes,
                        sl_scene *scene, scene_model_camera *camera, sl_error *err)
{
    memset(scene, 0, sizeof *scene);
    sl_option_values_default(&scene->options);
    parser p = {.name = name ? name : "scene", .base_dir = base_dir ? base_dir : "", .err = err,
                .model_camera = camera};
    snprintf(scene->path, sizeof scene->path, "%s", p.name);
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(json, size, &end, false);
    if (!root) {
        size_t at = end && end >= json && end <= json + size ? (size_t)(end - json) : 0;
        /* Nested too deep: cJSON stops at the bracket past its limit. */
        if (!scan_json(&p, json, at < size ? at + 1 : size, true, false))
            return false;
        size_t line, column;
        line_column(json, at, &line, &column);
        char near[24];
        size_t n = 0;
        for (size_t i = at; i < size && n < 16 && json[i] != '\n'; i++)
            near[n++] = json[i] >= 32 && json[i] < 127 ? json[i] : '?';
        near[n] = '\0';
        return sl_fail(err, SL_ERR_FORMAT, "%s:%zu:%zu: invalid JSON%s%s%s", p.name, line, column,
                       n ? " near '" : " (unexpected end of input)", near, n ? "'" : "");
    }
    bool ok = true;
    /* cJSON stops after the first value; anything but whitespace after it is a mistake. */
    for (size_t i = (size_t)(end - json); ok && i < size; i++) {
        if (json[i] != ' ' && json[i] != '\t' && json[i] != '\n' && json[i] != '\r') {
            size_t line, column;
            line_column(json, i, &line, &column);
            ok = sl_fail(err, SL_ERR_FORMAT, "%s:%zu:%zu: unexpected text after the JSON object", p.name, line,
                         column);
        }
    }
    ok = ok && scan_json(&p, json, size, false, true) && parse_document(&p, root, load_meshes, scene);
    cJSON_Delete(root);
    if (!ok)
        sl_scene_free(scene);
    return ok;
}

bool sl_scene_parse(const char *json, size_t size, const char *name, const char *base_dir, bool load_meshes,
                    sl_scene *scene, sl_error *err)
{
    return parse_scene(json, size, name, base_dir, load_meshes, scene, NULL, err);
}

bool sl_scene_parse_with_models(const char *json, size_t size, const char *name, const char *base_dir, sl_scene *scene,
                             scene_model_camera *camera, sl_error *err)
{
    return parse_scene(json, size, name, base_dir, true, scene, camera, err);
}

bool sl_scene_load(const char *path, sl_scene *scene, sl_error *err)
{
    memset(scene, 0, sizeof *scene);
    if (!sl_path_is_scene(path))
        return sl_scene_load_model_alone(path, scene, err);
    unsigned char *bytes;
    size_t size;
    if (!sl_read_file(path, SCENE_MAX_FILE_BYTES, &bytes, &size, err))
        return false;
    /* Paths in the scene are relative to the folder holding it. */
    char dir[SL_PATH_MAX] = "";
    const char *slash = strrchr(path, '/');
    if (slash) {
        size_t n = slash == path ? 1 : (size_t)(slash - path);
        if (n >= sizeof dir) {
            free(bytes);
            return sl_fail(err, SL_ERR_RANGE, "%s: path is longer than %d bytes", path, SL_PATH_MAX - 1);
        }
        memcpy(dir, path, n);
        dir[n] = '\0';
    }
    bool ok = sl_scene_parse((const char *)bytes, size, path, dir, true, scene, err);
    free(bytes);
    return ok;
}

void sl_scene_free(sl_scene *scene)
{
    if (!scene)
        return;
    if (scene->meshes)
        for (int i = 0; i < scene->mesh_count; i++)
            sl_mesh_free(&scene->meshes[i]);
    free(scene->meshes);
    free(scene->mesh_sources);
    free(scene->materials);
    free(scene->objects);
    free(scene->lights);
    for (int i = 0; scene->images && i < scene->image_count; i++)
        free(scene->images[i].bytes);
    free(scene->images);
    memset(scene, 0, sizeof *scene);
}

bool sl_scene_bounds(const sl_scene *scene, vec3 *lo, vec3 *hi)
{
    bool any = false;
    vec3 a = vec3s(INFINITY), b = vec3s(-INFINITY);
    for (int o = 0; o < scene->object_count; o++) {
        const sl_object *obj = &scene->objects[o];
        if (!scene->meshes || obj->mesh < 0 || obj->mesh >= scene->mesh_count)
            continue;
        const sl_mesh *m = &scene->meshes[obj->mesh];
        for (int v = 0; v < m->vertex_count; v++) {
            vec3 w = xyz(mat4_mul_vec4(obj->model, vec4_from3(m->positions[v], 1.0f)));
            a = vmin3(a, w);
            b = vmax3(b, w);
            any = true;
        }
    }
    if (any) {
        *lo = a;
        *hi = b;
    }
    return any;
}
