/* scene.c - the scene file (JSON, docs/scene-format.md) turned into an sl_scene.
 *
 * Owns: reading the file, the document's top level (its sections, in order: each read by its own
 * file, scene_read.h lists them), JSON syntax errors with their line and column, loading each
 * distinct mesh once the objects are read, and freeing a scene. A path that is not a scene file
 * is a model given alone (scene_default.c). */
#include "scene_read.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/image.h" /* sl_read_file */

#define SCENE_MAX_FILE_BYTES ((size_t)16 << 20)

static bool parse_document(scene_parser *p, const cJSON *root, bool load_meshes, sl_scene *scene)
{
    static const char *const keys[] = {"camera", "environment", "materials", "objects", "lights", "render", NULL};
    if (!cJSON_IsObject(root))
        return sl_scene_fail(p, NULL, SL_ERR_FORMAT, "expected a JSON object {...} at the top level");
    if (!sl_scene_check_keys(p, root, "", keys))
        return false;
    scene_name_index *sorted = NULL;
    int *first_user = NULL;
    bool *material_given = NULL;
    scene_source_map sources = {0};
    bool ok = sl_scene_parse_camera(p, sl_scene_member(root, "camera"), &scene->camera) &&
              sl_scene_parse_environment(p, sl_scene_member(root, "environment"), &scene->environment, &scene->options) &&
              sl_scene_parse_render(p, sl_scene_member(root, "render"), &scene->options) &&
              sl_scene_parse_materials(p, sl_scene_member(root, "materials"), scene, &sorted);
    const cJSON *objects = sl_scene_member(root, "objects");
    if (ok && objects && !cJSON_IsArray(objects))
        ok = sl_scene_fail(p, "objects", SL_ERR_FORMAT, "expected an array of objects [{\"shape\": ...}, ...]");
    if (ok) {
        size_t n = (size_t)(objects ? cJSON_GetArraySize(objects) : 0);
        scene->objects = calloc(n + 1, sizeof *scene->objects);
        scene->mesh_sources = calloc(n + 1, sizeof *scene->mesh_sources);
        first_user = calloc(n + 1, sizeof *first_user);
        material_given = calloc(n + 1, sizeof *material_given);
        if (!scene->objects || !scene->mesh_sources || !first_user || !material_given || !sl_scene_source_map_init(&sources, n))
            ok = sl_scene_fail(p, "objects", SL_ERR_MEMORY, "out of memory for %zu objects", n);
    }
    int named_materials = scene->material_count;
    for (const cJSON *e = objects && ok ? objects->child : NULL; e && ok; e = e->next) {
        char path[JSON_PATH_MAX];
        sl_scene_join_index(path, "objects", scene->object_count);
        sl_object *obj = &scene->objects[scene->object_count];
        ok = sl_scene_parse_object(p, e, path, scene, sorted, named_materials, &sources, first_user, obj,
                          &material_given[scene->object_count]);
        if (ok)
            scene->object_count++;
    }
    ok = ok && sl_scene_parse_lights(p, sl_scene_member(root, "lights"), scene);
    if (ok) {
        scene->meshes = calloc((size_t)scene->mesh_count + 1, sizeof *scene->meshes);
        if (!scene->meshes)
            ok = sl_scene_fail(p, "objects", SL_ERR_MEMORY, "out of memory for %d meshes", scene->mesh_count);
    }
    if (ok && load_meshes)
        ok = sl_scene_load_meshes(p, scene, first_user) &&
             sl_scene_expand_models(scene, material_given, first_user, p->name, p->model_camera, p->err) &&
             sl_scene_check_maps_have_uvs(p, scene);
    free(sorted);
    free(first_user);
    free(material_given);
    free(sources.slots);
    return ok;
}


static bool parse_scene(const char *json, size_t size, const char *name, const char *base_dir, bool load_meshes,
                        const sl_option_values *given, sl_scene *scene, sl_error *err)
{
    memset(scene, 0, sizeof *scene);
    sl_option_values_default(&scene->options);
    scene_parser p = {.name = name ? name : "scene", .base_dir = base_dir ? base_dir : "", .err = err, .given = given};
    snprintf(scene->path, sizeof scene->path, "%s", p.name);
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(json, size, &end, false);
    if (!root) {
        size_t at = end && end >= json && end <= json + size ? (size_t)(end - json) : 0;
        /* Nested too deep: cJSON stops at the bracket past its limit. */
        if (!sl_scene_scan_json(&p, json, at < size ? at + 1 : size, true, false))
            return false;
        size_t line, column;
        sl_scene_line_column(json, at, &line, &column);
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
            sl_scene_line_column(json, i, &line, &column);
            ok = sl_fail(err, SL_ERR_FORMAT, "%s:%zu:%zu: unexpected text after the JSON object", p.name, line,
                         column);
        }
    }
    ok = ok && sl_scene_scan_json(&p, json, size, false, true) && parse_document(&p, root, load_meshes, scene);
    cJSON_Delete(root);
    if (!ok)
        sl_scene_free(scene);
    return ok;
}

bool sl_scene_parse(const char *json, size_t size, const char *name, const char *base_dir, bool load_meshes,
                    sl_scene *scene, sl_error *err)
{
    return parse_scene(json, size, name, base_dir, load_meshes, NULL, scene, err);
}

sl_missing_textures sl_scene_missing_textures(const scene_parser *p, sl_missing_textures own)
{
    return p->given && sl_option_is_set(p->given, SL_OPT_MISSING_TEXTURES) ? p->given->missing_textures : own;
}

bool sl_scene_load(const char *path, sl_scene *scene, sl_error *err)
{
    return sl_scene_load_with(path, NULL, scene, err);
}

bool sl_scene_load_with(const char *path, const sl_option_values *given, sl_scene *scene, sl_error *err)
{
    memset(scene, 0, sizeof *scene);
    if (!sl_path_is_scene(path))
        return sl_scene_load_model_alone(path, given, scene, err);
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
    bool ok = parse_scene((const char *)bytes, size, path, dir, true, given, scene, err);
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
