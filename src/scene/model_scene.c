/* model_scene.c - model files in a scene: `{"model": "file.glb"}` objects expanded into
 * objects, meshes and materials, and the default scene around a model given alone
 * (`softlight render model.glb`).
 *
 * Owns: the expansion (one object per mesh instance, the scene object's transform on top of
 * the node's, a scene "material" overriding the file's), the mapping of the file's materials
 * onto softlight's, and the default scene (shipped environment, the file's first camera or one
 * framing the bounds). scene.c reads the "model" key and calls scene_expand_models.
 *
 * Materials, interim until scene materials gain textures and GGX (issue 13, "Materials"):
 * glTF metallic-roughness maps to Kd = baseColor (1 - metallic), Ks = mix(0.04, baseColor,
 * metallic) and the Phong exponent alpha = 2 / a^2 - 2 with a = max(r^2, 1e-4) (the Phong/GGX
 * equivalence; ERRATA.md: it misses GGX's tail); MTL maps Kd, Ks and Ns (the Phong exponent)
 * as they are. Textures, tangents, emissive, alpha modes and double-sidedness are imported
 * (model.h) but not yet drawn. */
#include "model.h"
#include "scene_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The scene reader's limit on the Phong exponent (scene.c MAX_ALPHA). */
#define MODEL_MAX_ALPHA 1e6f
/* The name assimp gives the material it adds when a file has none (AI_DEFAULT_MATERIAL_NAME). */
#define AI_DEFAULT_NAME "DefaultMaterial"
#define DEFAULT_ENVIRONMENT SL_SHADER_DIR "/../scenes/envmaps/studio.hdr"


/* One of the file's materials as softlight's (see the top of this file). */
static sl_material map_material(const sl_model_material *m, const char *prefix)
{
    sl_material out;
    snprintf(out.name, sizeof out.name, "%.31s/%.31s", prefix, m->name);
    if (m->kind == SL_MODEL_MAT_PHONG) {
        out.kd = m->kd;
        out.ks = m->ks;
        out.alpha = m->ns < MODEL_MAX_ALPHA ? m->ns : MODEL_MAX_ALPHA;
        return out;
    }
    vec3 base = xyz(m->base_color);
    out.kd = scale3(base, 1.0f - m->metallic);
    out.ks = vec3(mixf(0.04f, base.x, m->metallic), mixf(0.04f, base.y, m->metallic),
                  mixf(0.04f, base.z, m->metallic));
    float a = maxf(m->roughness * m->roughness, 1e-4f);
    out.alpha = minf(2.0f / (a * a) - 2.0f, MODEL_MAX_ALPHA);
    return out;
}

static bool grow(void **array, size_t count, size_t size)
{
    void *p = realloc(*array, (count ? count : 1) * size);
    if (!p)
        return false;
    *array = p;
    return true;
}

/* The base name of a path without its extension, for material and object names. */
static void base_name(const char *path, char out[32])
{
    const char *b = strrchr(path, '/');
    b = b ? b + 1 : path;
    size_t n = strcspn(b, ".");
    snprintf(out, 32, "%.*s", (int)(n < 31 ? n : 31), b);
}

/* The empty mesh each model source held until it was expanded goes; objects' indices follow. */
static void drop_placeholders(sl_scene *scene, int sources)
{
    int kept = 0;
    int *remap = calloc((size_t)scene->mesh_count, sizeof *remap);
    if (!remap)
        return; /* harmless: empty meshes no object draws */
    for (int i = 0; i < scene->mesh_count; i++) {
        remap[i] = kept;
        if (i < sources && scene->mesh_sources[i].kind == SL_MESH_MODEL) {
            sl_mesh_free(&scene->meshes[i]);
            continue;
        }
        scene->meshes[kept] = scene->meshes[i];
        scene->mesh_sources[kept] = scene->mesh_sources[i];
        kept++;
    }
    for (int o = 0; o < scene->object_count; o++)
        scene->objects[o].mesh = remap[scene->objects[o].mesh];
    scene->mesh_count = kept;
    free(remap);
}

bool scene_expand_models(sl_scene *scene, const bool *material_given, const int *first_user, const char *name,
                         scene_model_camera *camera, sl_error *err)
{
    int sources = scene->mesh_count;
    bool any = false;
    for (int i = 0; i < sources && !any; i++)
        any = scene->mesh_sources[i].kind == SL_MESH_MODEL;
    if (!any)
        return true;
    /* Each distinct model file once: its first mesh's and material's index in the scene. */
    int *mesh_base = calloc((size_t)sources, sizeof *mesh_base);
    int *material_base = calloc((size_t)sources, sizeof *material_base);
    sl_model *models = calloc((size_t)sources, sizeof *models);
    bool ok = mesh_base && material_base && models;
    if (!ok)
        sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for models", name);
    long long total_vertices = 0;
    for (int i = 0; ok && i < scene->mesh_count; i++)
        total_vertices += scene->meshes[i].vertex_count;
    int new_objects = 0;
    for (int i = 0; ok && i < sources; i++) {
        /* A copy: growing mesh_sources below moves the array. */
        const sl_mesh_source source = scene->mesh_sources[i], *src = &source;
        if (src->kind != SL_MESH_MODEL)
            continue;
        sl_model *m = &models[i];
        if (!sl_model_load(src->path, m, err)) {
            sl_error_prefix(err, "%s: objects[%d].model: ", name, first_user[i]);
            ok = false;
            break;
        }
        if (camera && !camera->has && m->has_camera) {
            camera->has = true;
            camera->camera = m->camera;
        }
        for (int k = 0; k < m->mesh_count; k++)
            total_vertices += m->meshes[k].mesh.vertex_count;
        if (total_vertices > SCENE_MAX_TOTAL_VERTICES) {
            ok = sl_fail(err, SL_ERR_RANGE, "%s: objects[%d].model: the scene's meshes have more than %d vertices in all",
                         name, first_user[i], SCENE_MAX_TOTAL_VERTICES);
            break;
        }
        /* Meshes move into the scene, tangents included (the model keeps empty ones). */
        mesh_base[i] = scene->mesh_count;
        ok = grow((void **)&scene->meshes, (size_t)(scene->mesh_count + m->mesh_count), sizeof *scene->meshes) &&
             grow((void **)&scene->mesh_sources, (size_t)(scene->mesh_count + m->mesh_count),
                  sizeof *scene->mesh_sources);
        for (int k = 0; ok && k < m->mesh_count; k++) {
            scene->meshes[scene->mesh_count] = m->meshes[k].mesh;
            memset(&m->meshes[k].mesh, 0, sizeof m->meshes[k].mesh);
            scene->mesh_sources[scene->mesh_count] = (sl_mesh_source){.kind = SL_MESH_MODEL, .slices = k};
            memcpy(scene->mesh_sources[scene->mesh_count].path, src->path, SL_PATH_MAX);
            scene->mesh_count++;
        }
        material_base[i] = scene->material_count;
        ok = ok && grow((void **)&scene->materials, (size_t)(scene->material_count + m->material_count),
                        sizeof *scene->materials);
        char prefix[32];
        base_name(src->path, prefix);
        for (int k = 0; ok && k < m->material_count; k++)
            scene->materials[scene->material_count++] = map_material(&m->materials[k], prefix);
        if (!ok)
            sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for the meshes of %s", name, src->path);
    }
    for (int o = 0; ok && o < scene->object_count; o++) {
        int mesh = scene->objects[o].mesh;
        new_objects += scene->mesh_sources[mesh].kind == SL_MESH_MODEL && mesh < sources
                           ? models[mesh].instance_count
                           : 1;
    }
    sl_object *objects = ok ? calloc((size_t)new_objects + 1, sizeof *objects) : NULL;
    if (ok && !objects)
        ok = sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for %d objects", name, new_objects);
    int n = 0;
    for (int o = 0; ok && o < scene->object_count; o++) {
        const sl_object *obj = &scene->objects[o];
        if (scene->mesh_sources[obj->mesh].kind != SL_MESH_MODEL || obj->mesh >= sources) {
            objects[n++] = *obj;
            continue;
        }
        const sl_model *m = &models[obj->mesh];
        for (int k = 0; k < m->instance_count; k++) {
            const sl_model_instance *inst = &m->instances[k];
            sl_object *out = &objects[n++];
            snprintf(out->name, sizeof out->name, "%.40s/%d", obj->name, k);
            out->mesh = mesh_base[obj->mesh] + inst->mesh;
            int file_material = m->meshes[inst->mesh].material;
            /* assimp's stand-in for "no material" (an OBJ without MTL) is the scene's default. */
            bool stand_in = strcmp(m->materials[file_material].name, AI_DEFAULT_NAME) == 0;
            out->material = material_given[o] || stand_in ? obj->material : material_base[obj->mesh] + file_material;
            out->model = mat4_mul(obj->model, inst->world);
        }
    }
    if (ok) {
        free(scene->objects);
        scene->objects = objects;
        scene->object_count = n;
        drop_placeholders(scene, sources);
    }
    for (int i = 0; models && i < sources; i++)
        sl_model_free(&models[i]);
    free(models);
    free(mesh_base);
    free(material_base);
    return ok;
}

/* ---- the default scene around a model ---- */

/* `s` as a JSON string's contents (quotes and backslashes escaped, control bytes as \u00XX). */
static bool json_escape(const char *s, char *out, size_t cap)
{
    size_t n = 0;
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        int w = c == '"' || c == '\\' ? snprintf(out + n, cap - n, "\\%c", c)
                : c < 32              ? snprintf(out + n, cap - n, "\\u%04x", c)
                                      : snprintf(out + n, cap - n, "%c", c);
        if (w < 0 || (size_t)w >= cap - n)
            return false;
        n += (size_t)w;
    }
    return true;
}

/* A camera looking at the bounds from the front (-Y) and a little above, far enough for the
 * bounding sphere to fit the default 45 degree field of view. */
static sl_camera frame_bounds(vec3 lo, vec3 hi, float fovy_deg)
{
    vec3 c = scale3(add3(lo, hi), 0.5f);
    float r = maxf(0.5f * length3(sub3(hi, lo)), 1e-3f);
    float d = 1.1f * r / sinf(0.5f * fovy_deg * (3.14159265f / 180.0f));
    vec3 dir;
    scene_safe_normalize(vec3(0.0f, -1.0f, 0.35f), &dir);
    return (sl_camera){.eye = add3(c, scale3(dir, d)),
                       .target = c,
                       .up = vec3(0.0f, 0.0f, 1.0f),
                       .fovy_deg = fovy_deg,
                       .znear = maxf(d - 2.0f * r, d * 1e-3f),
                       .zfar = d + 2.0f * r};
}

bool scene_load_model_alone(const char *path, sl_scene *scene, sl_error *err)
{
    char escaped[2 * SL_PATH_MAX], env[2 * SL_PATH_MAX];
    if (!json_escape(path, escaped, sizeof escaped) || !json_escape(DEFAULT_ENVIRONMENT, env, sizeof env))
        return sl_fail(err, SL_ERR_RANGE, "%s: path too long", path);
    char json[5 * SL_PATH_MAX];
    int n = snprintf(json, sizeof json, "{\"environment\": \"%s\", \"objects\": [{\"model\": \"%s\"}]}", env,
                     escaped);
    if (n < 0 || (size_t)n >= sizeof json)
        return sl_fail(err, SL_ERR_RANGE, "%s: path too long", path);
    scene_model_camera camera = {0};
    if (!scene_parse_with_models(json, (size_t)n, path, "", scene, &camera, err)) {
        /* "model.glb: objects[0].model: model.glb: ..." says the file twice; the user typed no
         * scene, so the message starts at the model. */
        const char *inner = err ? strstr(err->msg, "objects[0].model: ") : NULL;
        if (inner)
            memmove(err->msg, inner + 18, strlen(inner + 18) + 1);
        return false;
    }
    if (camera.has) {
        scene->camera = camera.camera;
    } else {
        vec3 lo, hi;
        if (sl_scene_bounds(scene, &lo, &hi))
            scene->camera = frame_bounds(lo, hi, scene->camera.fovy_deg);
    }
    return true;
}
