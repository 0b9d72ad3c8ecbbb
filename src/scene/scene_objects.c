/* scene_objects.c - the scene file's "objects" (docs/scene-format.md "objects"): what each draws
 * (an OBJ mesh, a built-in shape or a model file), its material and its transform; one mesh per
 * distinct source however many objects name it; building those meshes within the scene's limits
 * (scene_internal.h), and the check that a material with maps is drawn on meshes with texture
 * coordinates. Models are expanded into objects by model_scene.c. */
#include "scene_read.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_SLICES 64
#define DEFAULT_STACKS 32

/* "rotate": [ax, ay, az, degrees] or a list of those; the first listed is applied first. */
static bool parse_rotate(scene_parser *p, const cJSON *item, const char *path, mat4 *r)
{
    *r = mat4_identity();
    bool list = cJSON_IsArray(item) && item->child && cJSON_IsArray(item->child);
    int i = 0;
    for (const cJSON *e = list ? item->child : item; e; e = list ? e->next : NULL, i++) {
        char sub[JSON_PATH_MAX];
        if (list)
            sl_scene_join_index(sub, path, i);
        else
            snprintf(sub, sizeof sub, "%s", path);
        double v[4];
        if (!cJSON_IsArray(e) || cJSON_GetArraySize(e) != 4)
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "expected [ax, ay, az, degrees] or a list of them");
        if (!sl_scene_read_numbers(p, e, sub, 4, v))
            return false;
        vec3 axis;
        if (!sl_scene_safe_normalize(vec3(v[0], v[1], v[2]), &axis))
            return sl_scene_fail(p, sub, SL_ERR_RANGE, "the rotation axis must not be the zero vector");
        float angle = (float)(fmod(v[3], 360.0) * (3.14159265358979323846 / 180.0));
        *r = mat4_mul(mat4_rotate(axis, angle), *r);
    }
    return true;
}

/* Object -> world = T * R * S: scale about the origin, then rotate, then translate. */
static bool parse_transform(scene_parser *p, const cJSON *item, const char *path, mat4 *model)
{
    static const char *const keys[] = {"translate", "rotate", "scale", NULL};
    *model = mat4_identity();
    if (!item)
        return true;
    if (!sl_scene_check_keys(p, item, path, keys))
        return false;
    char sub[JSON_PATH_MAX];
    vec3 t = vec3s(0.0f), s = vec3s(1.0f);
    mat4 r = mat4_identity();
    const cJSON *v;
    if ((v = sl_scene_member(item, "translate"))) {
        sl_scene_join_key(sub, path, "translate");
        if (!sl_scene_read_vec3(p, v, sub, &t))
            return false;
    }
    if ((v = sl_scene_member(item, "rotate"))) {
        sl_scene_join_key(sub, path, "rotate");
        if (!parse_rotate(p, v, sub, &r))
            return false;
    }
    if ((v = sl_scene_member(item, "scale"))) {
        sl_scene_join_key(sub, path, "scale");
        if (cJSON_IsNumber(v)) {
            double x;
            if (!sl_scene_read_number(p, v, sub, &x))
                return false;
            s = vec3s((float)x);
        } else if (!cJSON_IsArray(v)) {
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "expected a number or an array of 3 numbers");
        } else if (!sl_scene_read_vec3(p, v, sub, &s)) {
            return false;
        }
        /* Negative scales would mirror the mesh and turn its front faces into back faces. */
        const float c[3] = {s.x, s.y, s.z};
        for (int i = 0; i < 3; i++)
            if (!(c[i] >= 1e-6f && c[i] <= 1e6f))
                return sl_scene_fail(p, sub, SL_ERR_RANGE, "%g is outside 1e-06..1e+06 (positive; no mirroring)",
                               (double)c[i]);
    }
    *model = mat4_mul(mat4_translate(t), mat4_mul(r, mat4_scale(s)));
    return true;
}

static bool same_source(const sl_mesh_source *a, const sl_mesh_source *b)
{
    return a->kind == b->kind && a->slices == b->slices && a->stacks == b->stacks &&
           a->missing_textures == b->missing_textures && strcmp(a->path, b->path) == 0;
}


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

bool sl_scene_source_map_init(scene_source_map *map, size_t sources)
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
static int source_mesh(scene_source_map *map, sl_scene *scene, int *first_user, const sl_mesh_source *src, int object)
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
void sl_scene_default_object_name(char out[SL_NAME_MAX], const char *mesh_text, const char *shape)
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

bool sl_scene_parse_object(scene_parser *p, const cJSON *item, const char *path, sl_scene *scene,
                         const scene_name_index *sorted, int named_materials, scene_source_map *sources, int *first_user,
                         sl_object *obj, bool *material_given)
{
    static const char *const keys[] = {"name",     "mesh",      "shape",            "model", "slices", "stacks",
                                       "material", "transform", "missing_textures", NULL};
    static const char *const shapes[] = {"sphere", "plane", "box"};
    static const sl_mesh_kind kinds[] = {SL_MESH_SPHERE, SL_MESH_PLANE, SL_MESH_BOX};
    if (!sl_scene_check_keys(p, item, path, keys))
        return false;
    char sub[JSON_PATH_MAX], shown[MASKED_MAX + 4];
    const cJSON *mesh = sl_scene_member(item, "mesh"), *shape = sl_scene_member(item, "shape"), *model = sl_scene_member(item, "model");
    if (!!mesh + !!shape + !!model > 1)
        return sl_scene_fail(p, path, SL_ERR_FORMAT, "has more than one of \"mesh\", \"shape\" and \"model\"; give one");
    if (!mesh && !shape && !model)
        return sl_scene_fail(p, path, SL_ERR_FORMAT,
                       "needs \"mesh\" (an .obj path), \"shape\" (\"sphere\", \"plane\" or \"box\") or \"model\" "
                       "(a glTF, OBJ, ... file)");
    sl_mesh_source src = {.kind = SL_MESH_OBJ};
    const char *shape_name = NULL;
    if (model) {
        sl_scene_join_key(sub, path, "model");
        src.kind = SL_MESH_MODEL;
        if (!sl_scene_read_path(p, model, sub, src.path))
            return false;
        mesh = model; /* the object's default name comes from the file's */
    } else if (mesh) {
        sl_scene_join_key(sub, path, "mesh");
        if (!sl_scene_read_path(p, mesh, sub, src.path))
            return false;
    } else {
        sl_scene_join_key(sub, path, "shape");
        if (!cJSON_IsString(shape))
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "expected \"sphere\", \"plane\" or \"box\"");
        for (int i = 0; i < 3 && !shape_name; i++)
            if (strcmp(shape->valuestring, shapes[i]) == 0)
                shape_name = shapes[i], src.kind = kinds[i];
        if (!shape_name)
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "unknown shape \"%s\" (expected sphere, plane or box)",
                           sl_scene_masked(shape->valuestring, 32, shown));
    }
    const cJSON *v;
    /* A model's texture that names no file: the object's choice, unless the command line gave one. */
    sl_missing_textures missing = SL_MISSING_TEXTURES_FAIL;
    if ((v = sl_scene_member(item, "missing_textures"))) {
        const sl_option *opt = &sl_options[SL_OPT_MISSING_TEXTURES];
        sl_scene_join_key(sub, path, "missing_textures");
        char words[64];
        sl_option_choices(opt, words, sizeof words);
        int value;
        if (src.kind != SL_MESH_MODEL)
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "only a model has missing_textures");
        if (!cJSON_IsString(v))
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "expected a string (%s)", words);
        if (!sl_option_parse(opt, v->valuestring, &value))
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "unknown %s \"%s\" (expected %s)", opt->name,
                                 sl_scene_masked(v->valuestring, 32, shown), words);
        missing = (sl_missing_textures)value;
    }
    if (src.kind == SL_MESH_MODEL)
        src.missing_textures = sl_scene_missing_textures(p, missing);
    if (src.kind == SL_MESH_SPHERE) {
        src.slices = DEFAULT_SLICES;
        src.stacks = DEFAULT_STACKS;
    }
    static const char *const tess[2] = {"slices", "stacks"};
    for (int i = 0; i < 2; i++) {
        if (!(v = sl_scene_member(item, tess[i])))
            continue;
        sl_scene_join_key(sub, path, tess[i]);
        if (src.kind != SL_MESH_SPHERE)
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "only a sphere has %s", tess[i]);
        bool ok = i == 0 ? sl_scene_read_int(p, v, sub, 3, SCENE_SPHERE_MAX_SLICES, &src.slices)
                         : sl_scene_read_int(p, v, sub, 2, SCENE_SPHERE_MAX_STACKS, &src.stacks);
        if (!ok)
            return false;
    }

    if ((v = sl_scene_member(item, "name"))) {
        sl_scene_join_key(sub, path, "name");
        if (!sl_scene_read_string(p, v, sub, obj->name, sizeof obj->name))
            return false;
    } else {
        sl_scene_default_object_name(obj->name, mesh ? mesh->valuestring : "", shape_name);
    }

    *material_given = sl_scene_member(item, "material") != NULL;
    if ((v = sl_scene_member(item, "material"))) {
        sl_scene_join_key(sub, path, "material");
        if (!cJSON_IsString(v))
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "expected a material name (a string)");
        obj->material = sl_scene_find_material(sorted, named_materials, v->valuestring);
        if (obj->material < 0)
            return sl_scene_fail(p, sub, SL_ERR_FORMAT, "no material named \"%s\"", sl_scene_masked(v->valuestring, 64, shown));
    } else {
        /* No material: the one named "default" if the scene defines it, else a built-in grey. */
        obj->material = sl_scene_find_material(sorted, named_materials, DEFAULT_MATERIAL_NAME);
        if (obj->material < 0) {
            obj->material = named_materials;
            if (scene->material_count == named_materials) {
                scene->materials[named_materials] = sl_scene_default_material(DEFAULT_MATERIAL_NAME);
                scene->material_count++;
            }
        }
    }

    sl_scene_join_key(sub, path, "transform");
    if (!parse_transform(p, sl_scene_member(item, "transform"), sub, &obj->model))
        return false;

    /* One mesh per distinct source. */
    obj->mesh = source_mesh(sources, scene, first_user, &src, (int)(obj - scene->objects));
    return true;
}

/* Build every distinct mesh. Each mesh is capped on its own (scene_internal.h); the scene as
 * a whole is capped too, so that many large meshes cannot add up to an absurd allocation. */
bool sl_scene_load_meshes(scene_parser *p, sl_scene *scene, const int *first_user)
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
bool sl_scene_check_maps_have_uvs(scene_parser *p, const sl_scene *scene)
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
        sl_scene_join_index(path, "objects", i);
        char shown[MASKED_MAX + 4];
        return sl_scene_fail(p, path, SL_ERR_FORMAT,
                       "material \"%s\" has a %s (%s) but the mesh %s has no texture coordinates (no vt on its faces)",
                       sl_scene_masked(m->name, 64, shown), sl_scene_map_keys[slot], scene->images[m->maps[slot].image].path,
                       scene->mesh_sources[o->mesh].path);
    }
    return true;
}
