/* model_scene.c - model files in a scene: `{"model": "file.glb"}` objects expanded into
 * objects, meshes and materials.
 *
 * Owns: the expansion (one object per mesh instance, the scene object's transform on top of
 * the node's, a scene "material" overriding the file's) and the mapping of the file's materials
 * onto softlight's. scene_objects.c reads the "model" key; scene.c and scene_default.c (the
 * default scene around a model given alone) call sl_scene_expand_models, which calls nothing of
 * theirs.
 *
 * Materials (docs/scene-format.md "Models"): glTF metallic-roughness becomes a GGX material. With
 * a metallicRoughnessTexture it is drawn per texel (scene.h sl_material.metallic: kd = the base
 * colour, the texture a metallic_roughness_map, the factors metallic and roughness); without one,
 * roughness = roughnessFactor, Kd = baseColor (1 - metallic), Ks = mix(0.04, baseColor, metallic),
 * baseColorTexture a kd_map (sRGB) whose texel multiplies Kd (exact: metallic is a constant factor),
 * and the ks_map too when metallic is 1 (Ks = baseColor exactly). normalTexture a normal_map;
 * occlusionTexture an occlusion_map with its strength; emissiveFactor and emissiveTexture (sRGB)
 * emissive and an emissive_map (MTL's Ke and map_Ke the same); MASK (and BLEND, which a G-buffer
 * cannot blend) a cutoff on kd_map's alpha. MTL-style materials keep the Phong set: Kd, Ks, Ns,
 * map_Kd and map_Ks (sRGB), map_Ns an alpha_map (exponent = Ns times its red channel), map_Bump /
 * norm a tangent-space normal_map. What a material has that the G-buffer cannot carry (a normal
 * scale, BLEND, ...) is not drawn, and one warning line per model names it.
 *
 * Images: a file becomes a scene image by its path; an embedded one (.glb, data URI) by its bytes,
 * copied into the scene ("MODEL#N"), so that the raster stage decodes each once either way. */
#include "model.h"
#include "scene_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The scene reader's limit on the Phong exponent (scene_materials.c MAX_ALPHA). */
#define MODEL_MAX_ALPHA 1e6f
/* The name assimp gives the material it adds when a file has none (AI_DEFAULT_MATERIAL_NAME). */
#define AI_DEFAULT_NAME "DefaultMaterial"

/* glTF sampler values (GL enums). */
enum { GL_NEAREST_ = 9728, GL_LINEAR_ = 9729, GL_NEAREST_MIPMAP_NEAREST_ = 9984, GL_CLAMP_ = 33071,
       GL_MIRROR_ = 33648 };

/* What a model has that is not drawn, gathered over its materials for the one warning line. */
enum {
    IGNORED_NORMAL_SCALE = 1 << 0, /* normalTexture.scale != 1: drawn at 1 */
    IGNORED_BLEND = 1 << 1,       /* alphaMode BLEND: drawn as MASK at 0.5 */
    IGNORED_WRAP_T = 1 << 2,      /* wrapT differs from wrapS: wrapS on both axes */
    IGNORED_UV_SET = 1 << 3,      /* a texture reads TEXCOORD_1..: read from TEXCOORD_0 */
    IGNORED_DECODED = 1 << 4,     /* an embedded image assimp decoded to texels: map dropped */
    IGNORED_MASK_CONSTANT = 1 << 5, /* MASK/BLEND without a base colour texture: drawn opaque */
    IGNORED_COUNT = 6
};
static const char *const IGNORED_NAMES[IGNORED_COUNT] = {
    "normalTexture.scale (drawn at 1)",
    "alphaMode BLEND (drawn as MASK at 0.5)",
    "wrapT differing from wrapS (wrapS used on both axes)",
    "texture coordinate sets other than 0 (set 0 used)",
    "embedded images stored as decoded texels (maps dropped)",
    "MASK without a base colour texture (drawn opaque)",
};

/* The scene image for one of the model's images in one colour space, added on first use (the
 * scene's rule: one image per (path, srgb)). Embedded bytes are copied: the model is freed after
 * the expansion, the scene keeps them until sl_scene_free. */
static bool scene_image_of(sl_scene *scene, const sl_model *model, int image, bool srgb, const char *used_by,
                           int *index, sl_error *err)
{
    const sl_model_image *im = &model->images[image];
    char path[SL_PATH_MAX];
    if (im->bytes)
        snprintf(path, sizeof path, "%.1000s#%d", model->path, im->embedded);
    else
        snprintf(path, sizeof path, "%s", im->path);
    for (int i = 0; i < scene->image_count; i++) {
        if (scene->images[i].srgb == srgb && strcmp(scene->images[i].path, path) == 0) {
            *index = i;
            return true;
        }
    }
    if (scene->image_count == SL_SCENE_MAX_IMAGES)
        return sl_fail(err, SL_ERR_RANGE, "%s: more than %d distinct images in one scene", model->path,
                       SL_SCENE_MAX_IMAGES);
    if (!scene->images && !(scene->images = calloc(SL_SCENE_MAX_IMAGES, sizeof *scene->images)))
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for the image table", model->path);
    sl_scene_image *img = &scene->images[scene->image_count];
    memset(img, 0, sizeof *img);
    if (im->bytes) {
        if (!(img->bytes = malloc(im->size)))
            return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for embedded image %d", model->path, im->embedded);
        memcpy(img->bytes, im->bytes, im->size);
        img->size = im->size;
    }
    memcpy(img->path, path, sizeof path);
    img->srgb = srgb;
    snprintf(img->used_by, sizeof img->used_by, "%s", used_by);
    *index = scene->image_count++;
    return true;
}

/* glTF's sampler onto a scene map's one wrap and three filters (docs/scene-format.md "Models"):
 * NEAREST minification, or NEAREST magnification with no or nearest-only minification, is
 * "nearest"; LINEAR minification without mips is "bilinear"; mipmapped or unset is
 * "trilinear". */
static void map_sampler(const sl_model_sampler *s, sl_material_map *map, unsigned *ignored)
{
    int ws = s->wrap_s, wt = s->wrap_t;
    map->wrap = ws == GL_CLAMP_ ? SL_MAP_CLAMP : ws == GL_MIRROR_ ? SL_MAP_MIRROR : SL_MAP_REPEAT;
    sl_map_wrap t = wt == GL_CLAMP_ ? SL_MAP_CLAMP : wt == GL_MIRROR_ ? SL_MAP_MIRROR : SL_MAP_REPEAT;
    if (t != map->wrap)
        *ignored |= IGNORED_WRAP_T;
    int mn = s->min_filter, mg = s->mag_filter;
    if (mn == GL_NEAREST_ || (mg == GL_NEAREST_ && (mn == 0 || mn == GL_NEAREST_MIPMAP_NEAREST_)))
        map->filter = SL_MAP_NEAREST;
    else if (mn == GL_LINEAR_)
        map->filter = SL_MAP_BILINEAR;
    else
        map->filter = SL_MAP_TRILINEAR;
}

/* A texture slot of the file's material as a scene map; false only on an error (an image
 * table full, out of memory). A slot without an image leaves the map unset. */
static bool map_texture(sl_scene *scene, const sl_model *model, const sl_model_texref *ref, bool srgb,
                        const char *used_by, sl_material_map *map, unsigned *ignored, sl_error *err)
{
    if (ref->image < 0)
        return true;
    if (model->images[ref->image].width > 0) {
        *ignored |= IGNORED_DECODED;
        return true;
    }
    if (ref->uv_set != 0)
        *ignored |= IGNORED_UV_SET;
    *map = (sl_material_map){.set = true, .uv_scale = ref->uv_scale, .uv_offset = ref->uv_offset};
    map_sampler(&ref->sampler, map, ignored);
    return scene_image_of(scene, model, ref->image, srgb, used_by, &map->image, err);
}

/* One of the file's materials as softlight's (see the top of this file). */
static bool map_material(sl_scene *scene, const sl_model *model, const sl_model_material *m, const char *prefix,
                         sl_material *out, unsigned *ignored, sl_error *err)
{
    memset(out, 0, sizeof *out);
    out->metallic = -1.0f;
    out->occlusion_strength = 1.0f;
    snprintf(out->name, sizeof out->name, "%.31s/%.31s", prefix, m->name);
    char used[320]; /* fits the format below; sl_scene_image.used_by keeps its first 255 */
    /* Messages start with the scene's path: a model given alone is its own scene, named once. */
    bool alone = strcmp(model->path, scene->path) == 0;
#define USED(slot)                                                                                           \
    (snprintf(used, sizeof used, "%.200s%smaterial \"%.31s\": %s", alone ? "" : model->path, alone ? "" : ": ", \
              m->name, slot),                                                                                  \
     used)
    bool ok;
    if (m->kind == SL_MODEL_MAT_PHONG) {
        out->brdf = SL_BRDF_PHONG;
        out->kd = m->kd;
        out->ks = m->ks;
        out->alpha = m->ns < MODEL_MAX_ALPHA ? m->ns : MODEL_MAX_ALPHA;
        ok = map_texture(scene, model, &m->base_color_tex, true, USED("map_Kd"), &out->maps[SL_MAP_KD], ignored,
                         err) &&
             map_texture(scene, model, &m->specular_tex, true, USED("map_Ks"), &out->maps[SL_MAP_KS], ignored, err) &&
             map_texture(scene, model, &m->metallic_roughness_tex, false, USED("map_Ns"), &out->maps[SL_MAP_ALPHA],
                         ignored, err) &&
             map_texture(scene, model, &m->normal_tex, false, USED("map_Bump"), &out->maps[SL_MAP_NORMAL], ignored,
                         err);
    } else {
        vec3 base = xyz(m->base_color);
        out->brdf = SL_BRDF_GGX;
        out->roughness = m->roughness;
        out->kd = scale3(base, 1.0f - m->metallic);
        out->ks = vec3(mixf(0.04f, base.x, m->metallic), mixf(0.04f, base.y, m->metallic),
                       mixf(0.04f, base.z, m->metallic));
        /* The Phong exponent of the same lobe (alpha = 2 / a^2 - 2), for readers that want one. */
        float a = maxf(m->roughness * m->roughness, 1e-4f);
        out->alpha = minf(2.0f / (a * a) - 2.0f, MODEL_MAX_ALPHA);
        ok = map_texture(scene, model, &m->base_color_tex, true, USED("baseColorTexture"), &out->maps[SL_MAP_KD],
                         ignored, err) &&
             map_texture(scene, model, &m->normal_tex, false, USED("normalTexture"), &out->maps[SL_MAP_NORMAL],
                         ignored, err);
        if (ok && m->metallic_roughness_tex.image >= 0) {
            /* per texel: the G-buffer program computes Kd and Ks from the base colour */
            out->kd = base;
            out->metallic = m->metallic;
            ok = map_texture(scene, model, &m->metallic_roughness_tex, false, USED("metallicRoughnessTexture"),
                             &out->maps[SL_MAP_METALLIC_ROUGHNESS], ignored, err);
        } else if (ok && m->metallic == 1.0f && out->maps[SL_MAP_KD].set) {
            /* A full metal's Ks is its base colour, texel included: the same image as ks_map. */
            out->maps[SL_MAP_KS] = out->maps[SL_MAP_KD];
        }
        if (ok && m->occlusion_tex.image >= 0) {
            ok = map_texture(scene, model, &m->occlusion_tex, false, USED("occlusionTexture"),
                             &out->maps[SL_MAP_OCCLUSION], ignored, err);
            out->occlusion_strength = m->occlusion_tex.scale < 0.0f   ? 0.0f
                                      : m->occlusion_tex.scale > 1.0f ? 1.0f
                                                                      : m->occlusion_tex.scale;
        }
        if (m->normal_tex.image >= 0 && m->normal_tex.scale != 1.0f)
            *ignored |= IGNORED_NORMAL_SCALE;
        /* MASK cuts where baseColorFactor.a * texel.a < alphaCutoff, i.e. texel.a < cutoff / factor.a. */
        if (m->alpha_mode != SL_ALPHA_OPAQUE) {
            float cutoff = m->alpha_mode == SL_ALPHA_BLEND ? 0.5f : m->alpha_cutoff;
            if (m->alpha_mode == SL_ALPHA_BLEND)
                *ignored |= IGNORED_BLEND;
            if (out->maps[SL_MAP_KD].set) {
                out->masked = true;
                out->alpha_cutoff = m->base_color.w > 0.0f ? minf(cutoff / m->base_color.w, 1.0f) : 1.0f;
            } else {
                *ignored |= IGNORED_MASK_CONSTANT;
            }
        }
    }
    /* glTF: emissive = emissiveFactor * emissiveTexture (sRGB); a texture under a zero factor emits nothing */
    out->emissive = m->emissive;
    if (ok && m->emissive_tex.image >= 0 && sl_material_extra(out))
        ok = map_texture(scene, model, &m->emissive_tex, true, USED("emissiveTexture"), &out->maps[SL_MAP_EMISSIVE],
                         ignored, err);
#undef USED
    sl_scene_material_finish(out);
    return ok;
}

/* The one warning line for a model with something not drawn, added to the scene's warnings (the
 * commands print them: library code writes nothing to stderr). */
static void warn_ignored(sl_scene *scene, const char *path, unsigned ignored)
{
    if (!ignored)
        return;
    char line[1024];
    int n = snprintf(line, sizeof line, "softlight: warning: %.300s: not drawn:", path);
    for (int i = 0; i < IGNORED_COUNT && n > 0 && (size_t)n < sizeof line; i++)
        if (ignored & (1u << i))
            n += snprintf(line + n, sizeof line - (size_t)n, "%s %s", n > 0 && line[n - 1] == ':' ? "" : ",",
                          IGNORED_NAMES[i]);
    size_t used = strlen(scene->warnings);
    snprintf(scene->warnings + used, sizeof scene->warnings - used, "%s\n", line);
}

/* The model's own warnings (the textures skipped), added to the scene's line by line while they
 * fit; the rest are counted in one last line. */
static void warn_model(sl_scene *scene, const sl_model *m)
{
    int left_out = m->warnings_left_out;
    for (const char *l = m->warnings; *l;) {
        const char *end = strchr(l, '\n');
        size_t n = end ? (size_t)(end - l) + 1 : strlen(l), used = strlen(scene->warnings);
        /* room kept for the count's line */
        if (used + n + 400 < sizeof scene->warnings) {
            memcpy(scene->warnings + used, l, n);
            scene->warnings[used + n] = '\0';
        } else {
            left_out++;
        }
        l += n;
    }
    if (left_out > 0) {
        size_t used = strlen(scene->warnings);
        snprintf(scene->warnings + used, sizeof scene->warnings - used,
                 "softlight: warning: %.300s: %d more missing textures not listed\n", m->path, left_out);
    }
}

static bool grow(void **array, size_t count, size_t size)
{
    void *p = realloc(*array, (count ? count : 1) * size);
    if (!p)
        return false;
    *array = p;
    return true;
}

/* The model's texture coordinates are glTF's (v = 0 at an image's first row, model.h); the
 * scene's are OBJ's and GL's (v = 0 at the bottom row, docs/scene-format.md "Texture maps"):
 * v -> 1 - v. The tangent (along dP/du) stays; the bitangent (along dP/dv) turns, so does its
 * handedness w. */
static void to_scene_uv(sl_mesh *mesh)
{
    for (int v = 0; mesh->texcoords && v < mesh->vertex_count; v++) {
        mesh->texcoords[v].y = 1.0f - mesh->texcoords[v].y;
        mesh->tangents[v].w = -mesh->tangents[v].w;
    }
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

/* The material at *index without its maps, appended once (the copy's name ends in "/plain") and
 * *index moved to it: a model may use one material on meshes with and without texture
 * coordinates, and the raster stage refuses maps on a mesh that has none. */
static bool untextured_copy(sl_scene *scene, int *index, sl_error *err)
{
    sl_material plain = scene->materials[*index];
    memset(plain.maps, 0, sizeof plain.maps);
    plain.masked = false;
    plain.occlusion_strength = 1.0f;
    sl_scene_material_finish(&plain); /* a metallic material's constants folded; emission kept */
    char name[SL_NAME_MAX];
    snprintf(name, sizeof name, "%.56s/plain", plain.name);
    memcpy(plain.name, name, sizeof name);
    for (int i = 0; i < scene->material_count; i++) {
        if (strcmp(scene->materials[i].name, plain.name) == 0) {
            *index = i;
            return true;
        }
    }
    if (!grow((void **)&scene->materials, (size_t)scene->material_count + 1, sizeof *scene->materials))
        return sl_fail(err, SL_ERR_MEMORY, "out of memory for materials");
    scene->materials[scene->material_count] = plain;
    *index = scene->material_count++;
    return true;
}

bool sl_scene_expand_models(sl_scene *scene, const bool *material_given, const int *first_user, const char *name,
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
        /* what a message about this model starts with: its object's JSON path; nothing for a model
         * given alone, whose own messages name it */
        char where[SL_PATH_MAX + 64] = "";
        if (first_user)
            snprintf(where, sizeof where, "%.*s: objects[%d].model: ", SL_PATH_MAX, name, first_user[i]);
        if (!sl_model_load_with(src->path, src->missing_textures, m, err)) {
            if (where[0])
                sl_error_prefix(err, "%s", where);
            ok = false;
            break;
        }
        warn_model(scene, m);
        if (camera && !camera->has && m->has_camera) {
            camera->has = true;
            camera->camera = m->camera;
        }
        for (int k = 0; k < m->mesh_count; k++)
            total_vertices += m->meshes[k].mesh.vertex_count;
        if (total_vertices > SCENE_MAX_TOTAL_VERTICES) {
            ok = sl_fail(err, SL_ERR_RANGE, "%sthe scene's meshes have more than %d vertices in all", where,
                         SCENE_MAX_TOTAL_VERTICES);
            break;
        }
        /* Meshes move into the scene, tangents included (the model keeps empty ones). */
        mesh_base[i] = scene->mesh_count;
        ok = grow((void **)&scene->meshes, (size_t)(scene->mesh_count + m->mesh_count), sizeof *scene->meshes) &&
             grow((void **)&scene->mesh_sources, (size_t)(scene->mesh_count + m->mesh_count),
                  sizeof *scene->mesh_sources);
        for (int k = 0; ok && k < m->mesh_count; k++) {
            to_scene_uv(&m->meshes[k].mesh);
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
        if (!ok) {
            sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for the meshes of %s", name, src->path);
            break;
        }
        unsigned ignored = 0;
        for (int k = 0; ok && k < m->material_count; k++) {
            ok = map_material(scene, m, &m->materials[k], prefix, &scene->materials[scene->material_count], &ignored,
                              err);
            scene->material_count += ok;
        }
        if (!ok) {
            if (where[0])
                sl_error_prefix(err, "%s", where);
            break;
        }
        warn_ignored(scene, src->path, ignored);
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
            /* A file's textured material on a mesh without texture coordinates: its constants only. */
            if (out->material != obj->material && !scene->meshes[out->mesh].texcoords &&
                sl_material_has_maps(&scene->materials[out->material]))
                ok = untextured_copy(scene, &out->material, err);
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
