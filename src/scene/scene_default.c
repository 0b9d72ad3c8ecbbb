/* scene_default.c - the default scene around a model file given alone (`softlight render
 * model.glb`, docs/scene-format.md "Models"): built as a structure, not read from a file. The
 * shipped studio environment, the default camera, options and material, one object whose mesh is
 * the model, expanded by model_scene.c; then the file's first camera, or one framing the bounds. */
#include "scene_read.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "softlight/data.h"

/* The shipped environment lighting a model given alone, in the data directory (softlight/data.h). */
#define DEFAULT_ENVIRONMENT "scenes/envmaps/studio.hdr"

/* A camera looking at the bounds from the front (-Y) and a little above, far enough for the
 * bounding sphere to fit the default 45 degree field of view. */
static sl_camera frame_bounds(vec3 lo, vec3 hi, float fovy_deg)
{
    vec3 c = scale3(add3(lo, hi), 0.5f);
    float r = maxf(0.5f * length3(sub3(hi, lo)), 1e-3f);
    float d = 1.1f * r / sinf(0.5f * fovy_deg * (3.14159265f / 180.0f));
    /* From the front and a little above; a flat model (a plaque, a floor plan) is seen from the
     * side of its largest face instead, which the front view would show edge-on or nearly so:
     * the view's projected area of the bounds is compared with that face's. */
    vec3 e = sub3(hi, lo), dir;
    float front = 0.94f * e.x * e.z + 0.33f * e.x * e.y, face_x = e.y * e.z, face_z = e.x * e.y;
    vec3 view = vec3(0.0f, -1.0f, 0.35f);
    if (front < 0.25f * maxf(face_x, face_z))
        view = face_x >= face_z ? vec3(-1.0f, -0.3f, 0.35f) : vec3(0.0f, -0.6f, 1.0f);
    sl_scene_safe_normalize(view, &dir);
    return (sl_camera){.eye = add3(c, scale3(dir, d)),
                       .target = c,
                       .up = vec3(0.0f, 0.0f, 1.0f),
                       .fovy_deg = fovy_deg,
                       .znear = maxf(d - 2.0f * r, d * 1e-3f),
                       .zfar = d + 2.0f * r};
}

/* The scene's parts: one material, one object, one mesh source (the model), loaded. */
static bool build(scene_parser *p, const char *path, sl_scene *scene)
{
    static const int first_user[1] = {0};
    static const bool material_given[1] = {false};
    scene->materials = calloc(1, sizeof *scene->materials);
    scene->objects = calloc(1, sizeof *scene->objects);
    scene->mesh_sources = calloc(1, sizeof *scene->mesh_sources);
    scene->meshes = calloc(2, sizeof *scene->meshes);
    if (!scene->materials || !scene->objects || !scene->mesh_sources || !scene->meshes)
        return sl_fail(p->err, SL_ERR_MEMORY, "%s: out of memory for the default scene", path);
    scene->materials[0] = sl_scene_default_material(DEFAULT_MATERIAL_NAME);
    scene->material_count = 1;
    scene->mesh_sources[0] = (sl_mesh_source){.kind = SL_MESH_MODEL,
                                              .missing_textures = sl_scene_missing_textures(p, SL_MISSING_TEXTURES_FAIL)};
    snprintf(scene->mesh_sources[0].path, sizeof scene->mesh_sources[0].path, "%s", path);
    scene->mesh_count = 1;
    sl_object *obj = &scene->objects[0];
    *obj = (sl_object){.mesh = 0, .material = 0, .model = mat4_identity()};
    sl_scene_default_object_name(obj->name, path, NULL);
    scene->object_count = 1;
    return sl_scene_load_meshes(p, scene, first_user) &&
           sl_scene_expand_models(scene, material_given, NULL, p->name, p->model_camera, p->err) &&
           sl_scene_check_maps_have_uvs(p, scene);
}

bool sl_scene_load_model_alone(const char *path, const sl_option_values *given, sl_scene *scene, sl_error *err)
{
    memset(scene, 0, sizeof *scene);
    char env_path[SL_PATH_MAX];
    if (!sl_data_dir())
        return sl_fail(err, SL_ERR_IO,
                       "%s: no default environment: softlight's data directory (shaders/, scenes/) was not "
                       "found; set SOFTLIGHT_DATA_DIR",
                       path);
    if (strlen(path) >= SL_PATH_MAX || !sl_data_path(DEFAULT_ENVIRONMENT, env_path, sizeof env_path))
        return sl_fail(err, SL_ERR_RANGE, "%s: path too long", path);
    scene_model_camera camera = {0};
    scene_parser p = {.name = path, .base_dir = "", .err = err, .model_camera = &camera, .given = given};
    snprintf(scene->path, sizeof scene->path, "%s", path);
    sl_option_values_default(&scene->options);
    snprintf(scene->environment.hdr_path, sizeof scene->environment.hdr_path, "%s", env_path);
    if (!sl_scene_parse_camera(&p, NULL, &scene->camera) || !build(&p, path, scene)) {
        sl_scene_free(scene);
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
