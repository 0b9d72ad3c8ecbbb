/* model.h - a model file (glTF 2.0, .glb, OBJ+MTL, COLLADA, PLY, STL, ... anything assimp reads)
 * as an intermediate description the scene turns into objects, meshes and materials.
 *
 * Consumes: a file through Debian's assimp (its C API), or bytes in memory (the fuzz target).
 * Produces: an sl_model: validated triangle meshes (smooth normals where the file has none,
 * UVs, tangents), one instance per (node, mesh) with the node's world transform, materials as
 * glTF metallic-roughness parameters with texture references, the images those name (a file
 * path checked to exist, or an embedded image's bytes), and the file's first camera.
 *
 * Axes: assimp's output is Y-up (glTF's convention, and what its other importers convert to);
 * softlight's world is Z-up, so every instance transform and the camera get +90 degrees about
 * +X on the left ((x, y, z) -> (x, -z, y)).
 * Does not: animation, skins, morph targets, lights, points and lines (dropped), KHR extensions
 * beyond what assimp maps onto its material keys. */
#ifndef SL_MODEL_H
#define SL_MODEL_H

#include "scene.h"

/* Limits of one model file: far above the models softlight is meant to show, far below what
 * exhausts memory by accident (a 20-byte glTF can claim a 4 GiB buffer). */
#define SL_MODEL_MAX_FILE_BYTES ((size_t)256 << 20)
#define SL_MODEL_MAX_MESHES 4096
#define SL_MODEL_MAX_INSTANCES 65536
#define SL_MODEL_MAX_MATERIALS 4096
#define SL_MODEL_MAX_IMAGES 1024
#define SL_MODEL_MAX_NODE_DEPTH 256
#define SL_MODEL_MAX_NODES 65536
/* An import (sl_model_load) runs in a child process whose address space may grow by BASE +
 * PER_BYTE x (the file's bytes, with a .gltf's declared buffers) and which may run BASE + one
 * second per MIB_PER_SECOND MiB: a 10 MB file gets 1008 MiB and 12 s, a 256 MiB file 6.8 GiB
 * and 74 s. Measured (softlight info on generated OBJ grids, 2 cores): 11 MB imports in 0.6 s
 * at a 190 MiB peak, 66 MB in 8 s at 1 GiB (15x the file, against 24x allowed). */
#define SL_MODEL_IMPORT_MEMORY_BASE ((size_t)768 << 20)
#define SL_MODEL_IMPORT_MEMORY_PER_BYTE 24
#define SL_MODEL_IMPORT_SECONDS_BASE 10
#define SL_MODEL_IMPORT_MIB_PER_SECOND 4

/* glTF's alphaMode. BLEND is kept as a description; the scene draws it as MASK at 0.5 (no sorting
 * of transparent surfaces in a deferred G-buffer). */
typedef enum { SL_ALPHA_OPAQUE, SL_ALPHA_MASK, SL_ALPHA_BLEND } sl_alpha_mode;

/* glTF sampler values (GL enums, as glTF writes them); 0 = not given (glTF: repeat, auto filter). */
typedef struct {
    int wrap_s, wrap_t;         /* 10497 repeat, 33071 clamp to edge, 33648 mirrored repeat */
    int mag_filter, min_filter; /* 9728 nearest, 9729 linear, 9984..9987 mipmapped */
} sl_model_sampler;

/* One texture slot of a material: the image (index into sl_model.images, -1 = none), the
 * texture coordinate set it reads, its sampler, its scale (normalTexture.scale,
 * occlusionTexture.strength; 1 otherwise) and its texture-coordinate transform. */
typedef struct {
    int image;
    int uv_set;
    sl_model_sampler sampler;
    float scale;
    vec2 uv_scale, uv_offset; /* the slot reads uv * uv_scale + uv_offset (glTF's KHR_texture_transform) */
} sl_model_texref;

/* Where a material came from: glTF's metallic-roughness, or an MTL-style Phong set (OBJ,
 * COLLADA, ...: Kd, Ks, Ns), which the scene maps differently (docs/scene-format.md). */
typedef enum { SL_MODEL_MAT_METALLIC_ROUGHNESS, SL_MODEL_MAT_PHONG } sl_model_material_kind;

typedef struct {
    char name[SL_NAME_MAX];
    sl_model_material_kind kind;
    /* glTF metallic-roughness (also filled for Phong materials: base = Kd, metallic 0). */
    vec4 base_color; /* linear RGBA */
    float metallic, roughness;
    vec3 emissive; /* linear RGB */
    sl_alpha_mode alpha_mode;
    float alpha_cutoff; /* MASK: discard below this (glTF default 0.5) */
    bool double_sided;
    /* Phong (kind == SL_MODEL_MAT_PHONG): MTL's Kd, Ks and Ns (the Phong exponent). */
    vec3 kd, ks;
    float ns;
    sl_model_texref base_color_tex; /* sRGB; MTL map_Kd */
    sl_model_texref metallic_roughness_tex; /* linear: G roughness, B metallic; MTL map_Ns */
    sl_model_texref normal_tex;    /* linear, tangent space; MTL map_Bump / norm */
    sl_model_texref occlusion_tex; /* linear, R */
    sl_model_texref emissive_tex;  /* sRGB */
    sl_model_texref specular_tex;  /* MTL map_Ks (sRGB); none for glTF */
} sl_model_material;

/* An image a material names: a file (path resolved against the model's folder, checked to
 * exist) or bytes embedded in the model (.glb buffer views, data URIs). Embedded bytes are the
 * encoded file (PNG, JPEG: `format` its extension hint) or, when assimp decoded it, `width` x
 * `height` texels of 4 bytes (B, G, R, A as assimp's aiTexel). */
typedef struct {
    char path[SL_PATH_MAX]; /* "" when embedded */
    unsigned char *bytes;   /* embedded: owned; NULL for a file */
    size_t size;
    int width, height; /* embedded and decoded; 0 when `bytes` is an encoded file */
    char format[9];    /* embedded: "png", "jpg", ... as assimp reports it */
    int embedded;      /* the file's embedded texture index; -1 for a file */
} sl_model_image;

typedef struct {
    sl_mesh mesh;   /* validated: finite positions, unit normals, indices in range; with UVs,
                       unit tangents with handedness w = +-1 (mesh.tangents) */
    int material;   /* index into sl_model.materials */
} sl_model_mesh;

/* One mesh placed by one node: the node's transform composed from the root (then to Z-up). */
typedef struct {
    int mesh;
    mat4 world;
} sl_model_instance;

typedef struct {
    char path[SL_PATH_MAX]; /* the file, as given */
    sl_model_mesh *meshes;
    int mesh_count;
    sl_model_instance *instances;
    int instance_count;
    sl_model_material *materials;
    int material_count;
    sl_model_image *images;
    int image_count;
    bool has_camera; /* the file's first camera, placed by its node, in Z-up world space */
    sl_camera camera;
    /* What was imported but is not drawn, one line each ending in "\n" ("" when none): with
     * SL_MISSING_TEXTURES_SKIP, each missing texture (model, material, file). Lines that do not
     * fit are counted in warnings_left_out. The commands print them; the library writes nothing. */
    char warnings[2048];
    int warnings_left_out;
} sl_model;

/* Import a model file. Errors name the file: "bad.gltf: buffer 0: cannot read bad.bin". A
 * texture that names no file refuses the model (SL_MISSING_TEXTURES_FAIL, what sl_model_load
 * does) or is dropped from its material with a line in model->warnings (SL_MISSING_TEXTURES_SKIP). */
bool sl_model_load(const char *path, sl_model *model, sl_error *err);
bool sl_model_load_with(const char *path, sl_missing_textures missing, sl_model *model, sl_error *err);
/* Import from memory; `hint` is the format's extension ("gltf", "glb", "obj"); `name` starts
 * messages. External files (.bin, images, .mtl) cannot be reached from memory: a file naming
 * one fails to import. */
bool sl_model_load_memory(const void *data, size_t size, const char *hint, const char *name, sl_model *model,
                          sl_error *err);
/* Frees everything and zeroes the model; safe on a zeroed model. */
void sl_model_free(sl_model *model);

/* Whether `path` names a scene file (.json) rather than a model for the importer. */
bool sl_path_is_scene(const char *path);

#endif
