/* scene.h - what a frame is made of: meshes, materials, lights, camera, environment, settings.
 *
 * Consumes: a scene file (JSON, docs/scene-format.md) and the OBJ meshes it names.
 * Produces: an sl_scene whose meshes are validated (indices in range, finite
 * positions, unit normals) and whose materials are linear RGB. Paths inside
 * the scene are resolved relative to the scene file when it is loaded.
 *
 * World space is Z-up, right-handed (docs/conventions.md "Coordinate frames"). Colours are linear RGB.
 * Does not: model a scene graph, animation, textures per object (materials carry the maps), decode
 * images (it names them), or cameras other than pinhole. */
#ifndef SL_SCENE_H
#define SL_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <softlight/glsl.h>
#include <softlight/scene.h>

#include "../core/error.h"
#include "../core/options.h"

#define SL_NAME_MAX 64
#define SL_PATH_MAX 1024

/* sl_mesh (softlight/scene.h): `normals` always present (computed angle-weighted when the OBJ
 * has none); with texcoords, tangents from positions and texture coordinates for meshes without
 * analytic ones (mesh.c, sl_scene_compute_tangents). */

/* The texture maps a material may name (docs/scene-format.md "Texture maps"). Each multiplies the
 * material's constant: kd = Kd * kd_map.rgb, ks = Ks * ks_map.rgb, alpha = alpha * alpha_map.r;
 * normal_map perturbs the normal in tangent space (+Y up, OpenGL and glTF); mask_map.r, or
 * kd_map's alpha when there is no mask_map, is compared with alpha_cutoff (discard below it).
 * glTF's three more: metallic_roughness_map (G roughness, B metallic, times the factors; the
 * material's kd is then the base colour), occlusion_map (R, with occlusion_strength: scales the
 * image-based terms) and emissive_map (times emissive, added to the radiance). */
typedef enum {
    SL_MAP_KD,
    SL_MAP_KS,
    SL_MAP_ALPHA,
    SL_MAP_NORMAL,
    SL_MAP_MASK,
    SL_MAP_METALLIC_ROUGHNESS,
    SL_MAP_OCCLUSION,
    SL_MAP_EMISSIVE,
    SL_MAP_COUNT
} sl_map_slot;
typedef enum { SL_MAP_REPEAT, SL_MAP_CLAMP, SL_MAP_MIRROR } sl_map_wrap;
typedef enum { SL_MAP_TRILINEAR, SL_MAP_BILINEAR, SL_MAP_NEAREST } sl_map_filter;
typedef struct {
    bool set;               /* this slot has a map (a zeroed material has none) */
    int image;              /* index into scene->images */
    sl_map_wrap wrap;       /* both axes */
    sl_map_filter filter;   /* trilinear: LINEAR_MIPMAP_LINEAR / LINEAR; bilinear: LINEAR / LINEAR;
                               nearest: NEAREST / NEAREST (GL's min / mag filters) */
    vec2 uv_scale, uv_offset; /* the map reads texture coordinate uv * uv_scale + uv_offset */
} sl_material_map;

/* An image file named by materials, loaded once per scene however many maps use it: the key is
 * the resolved path and the colour space. Decoding is the raster stage's (src/raster/texture.h,
 * sl_scene_textures_load); the scene only says which files and how. An image embedded in a model
 * (.glb buffer view, data URI) has no file: the scene owns its encoded bytes (PNG, JPEG), and
 * `path` is "MODEL#N" (its N-th embedded texture), for the key and for messages. */
typedef struct {
    char path[SL_PATH_MAX];   /* resolved; "MODEL#N" for an embedded image */
    unsigned char *bytes;     /* embedded: the encoded file, owned (sl_scene_free); NULL for a file */
    size_t size;
    bool srgb;                /* 8-bit colour decoded with the sRGB curve (GL_SRGB8 / SRGB8_ALPHA8) */
    char used_by[256];        /* the first map naming it, as a JSON path ("materials.leaf.kd_map"), for messages */
} sl_scene_image;

/* The microfacet set of a material's specular lobe (docs/lighting.md "Phong and GGX"). */
typedef enum {
    SL_BRDF_PHONG = 0, /* the specification's set: D with the Phong exponent alpha */
    SL_BRDF_GGX,       /* GGX D and height-correlated Smith G, roughness r */
} sl_brdf;

/* The specification's material: Kd (diffuse albedo), Ks (Fresnel reflectance at
 * normal incidence, Schlick), alpha (Phong exponent, 0 = rough .. large = mirror); or, with
 * brdf = GGX, roughness (perceptual, glTF's, 0 = mirror .. 1) in place of alpha;
 * optionally modulated by texture maps. */
typedef struct {
    char name[SL_NAME_MAX];
    vec3 kd, ks;
    float alpha;
    sl_brdf brdf;
    float roughness; /* GGX only */
    /* glTF metallic-roughness per texel (metallic >= 0; -1 otherwise): kd is the base colour, ks
     * unused; the textured program computes kd = base (1 - m), ks = mix(0.04, base, m) with
     * m = metallic * metallic_roughness_map.b, roughness * metallic_roughness_map.g. The scene
     * reader folds a metallic material without kd_map and metallic_roughness_map into kd, ks. */
    float metallic;
    float occlusion_strength; /* occlusion = 1 + strength (occlusion_map.r - 1); 1 without a map */
    vec3 emissive;            /* linear RGB radiance added, times emissive_map.rgb (sRGB) */
    sl_material_map maps[SL_MAP_COUNT];
    bool textured;       /* drawn with the textured G-buffer program: some map is set, or it writes
                            the G-buffer's extra channels (sl_material_extra) */
    bool masked;         /* discard where the coverage (mask_map.r, else kd_map.a) < alpha_cutoff */
    float alpha_cutoff;  /* 0..1; default 0.5 (glTF's) when a mask_map is given */
} sl_material;

/* Whether a material writes the G-buffer's extra channels (occlusion, emission: gbuffer.h
 * sl_gbuffer_extra), which a scene allocates only when one of its materials does. */
static inline bool sl_material_extra(const sl_material *m)
{
    return m->maps[SL_MAP_OCCLUSION].set || m->emissive.x > 0.0f || m->emissive.y > 0.0f || m->emissive.z > 0.0f;
}
/* Whether a material samples any map (textured may be set for the extra channels alone). */
static inline bool sl_material_has_maps(const sl_material *m)
{
    for (int slot = 0; slot < SL_MAP_COUNT; slot++)
        if (m->maps[slot].set)
            return true;
    return false;
}

typedef struct {
    char name[SL_NAME_MAX];
    int mesh;      /* index into scene->meshes */
    int material;  /* index into scene->materials */
    mat4 model;    /* object -> world */
} sl_object;

typedef struct {
    vec3 position;
    vec3 color;      /* linear RGB */
    float intensity; /* radiant intensity scale: radiance contribution is color*intensity/d^2 */
    bool shadow;     /* casts shadows (its "shadow" key; --shadows casts them all): src/shadow */
} sl_point_light;

typedef struct {
    char hdr_path[SL_PATH_MAX];        /* resolved; "" = none (black environment) */
    char irradiance_path[SL_PATH_MAX]; /* resolved; "" = compute from hdr */
    float rotation_deg;                /* about +Z */
    /* the intensity is an option: scene->options.env_intensity */
} sl_environment_desc;


/* Where each of scene->meshes came from: an OBJ file, a built-in shape or a model file (through
 * assimp, scene/model.h). Objects naming the same source share one mesh. A model's source is
 * first one empty mesh; loading appends the model's meshes (each SL_MESH_MODEL with the path
 * and `slices` = its index in the file) and replaces the object by one per mesh instance. */
typedef enum { SL_MESH_OBJ, SL_MESH_SPHERE, SL_MESH_PLANE, SL_MESH_BOX, SL_MESH_MODEL } sl_mesh_kind;
typedef struct {
    sl_mesh_kind kind;
    char path[SL_PATH_MAX]; /* SL_MESH_OBJ, SL_MESH_MODEL: resolved file path; "" otherwise */
    int slices, stacks;     /* SL_MESH_SPHERE: tessellation; SL_MESH_MODEL: slices = mesh index; 0 otherwise */
    sl_missing_textures missing_textures; /* SL_MESH_MODEL: a texture that names no file (options.h) */
} sl_mesh_source;

/* The scene (opaque in softlight/scene.h). */
struct sl_scene {
    char path[SL_PATH_MAX]; /* the scene file, as given */
    sl_camera camera;
    sl_environment_desc environment;
    sl_option_values options; /* the options the file gives ("render", environment.intensity), each
                                 marked set; the others at their defaults (core/options.h) */
    sl_mesh *meshes;
    int mesh_count;
    sl_material *materials;
    int material_count;
    sl_object *objects;
    int object_count;
    sl_point_light *lights;
    int light_count;
    sl_mesh_source *mesh_sources; /* mesh_count entries, parallel to meshes */
    char warnings[2048];          /* what loads but is not drawn (model import), one line each ending
                                     in "\n", "" when none: the commands print it to stderr */
    sl_scene_image *images;       /* image_count distinct image files the materials' maps name */
    int image_count;
};

/* Distinct image files one scene may name (each is a texture with its mips in memory). */
#define SL_SCENE_MAX_IMAGES 64

/* Load a scene file and every mesh it names (image files are only named: the raster stage
 * decodes them, sl_scene_textures_load). On failure the scene is empty and
 * err names the file and JSON path, e.g. `objects[3].material: no material named "gold"`.
 * A path that does not end in .json is a model file (sl_path_is_scene, scene/model.h): the
 * default scene around it (docs/scene-format.md, "Models"). */
bool sl_scene_load(const char *path, sl_scene *scene, sl_error *err);
/* The same with the command line's record (`given`, NULL: none): the options the loading reads
 * (missing-textures: when given, it holds for every model over the scene file's keys). */
bool sl_scene_load_with(const char *path, const sl_option_values *given, sl_scene *scene, sl_error *err);
/* Parse scene JSON from memory; `base_dir` resolves relative paths ("" or NULL = cwd); `name`
 * starts every error message. With `load_meshes` false no geometry is built: OBJ files are not
 * opened and shapes are not tessellated, every mesh is empty (0 vertices) and only
 * mesh_sources says what it would be (what the fuzz target and most tests use).
 * `scene` is overwritten (not freed first); on failure it is left empty. */
bool sl_scene_parse(const char *json, size_t size, const char *name, const char *base_dir, bool load_meshes,
                    sl_scene *scene, sl_error *err);
/* Frees everything and zeroes the scene; safe on a zeroed or partially built scene. */
void sl_scene_free(sl_scene *scene);

/* sl_scene_bounds (softlight/scene.h): every vertex transformed; false when the scene has no
 * geometry (no objects, or meshes not loaded). */

/* Meshes (mesh.c, obj.c, shapes.c). */
bool sl_mesh_parse_obj(const char *text, size_t size, const char *name, sl_mesh *mesh, sl_error *err);
/* Checks indices in range, finite positions and normals; false with a reason. */
bool sl_mesh_validate(const sl_mesh *mesh, const char *name, sl_error *err);
void sl_mesh_compute_normals(sl_mesh *mesh); /* angle-weighted vertex normals */
/* sl_mesh_load_obj, sl_mesh_free and the built-in shapes (sl_mesh_sphere, sl_mesh_plane,
 * sl_mesh_box) are public: softlight/scene.h. */

#endif
