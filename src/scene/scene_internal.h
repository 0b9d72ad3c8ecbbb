/* scene_internal.h - helpers shared by the files of src/scene (not part of the public API).
 *
 * mesh.c owns mesh storage and normal generation; obj.c and shapes.c build meshes through
 * these so that every mesh is allocated, sized and normalised in one way. */
#ifndef SL_SCENE_INTERNAL_H
#define SL_SCENE_INTERNAL_H

#include "model.h"
#include "scene.h"

/* Size caps: far above any mesh softlight renders at interactive rates, far below
 * what would overflow an int or a uint32 index, or exhaust memory by accident. */
#define SCENE_MAX_VERTICES (1 << 24)
#define SCENE_MAX_TRIANGLES (1 << 25)
/* Sphere tessellation limits: 1024 x 512 is ~1M triangles, far past visual need. */
#define SCENE_SPHERE_MAX_SLICES 1024
#define SCENE_SPHERE_MAX_STACKS 512
/* All meshes of one scene together (about 1 GB of vertex data at this cap). */
#define SCENE_MAX_TOTAL_VERTICES (1 << 25)

/* Allocate positions, normals, indices (and texcoords and tangents when asked) for the given counts; the
 * arrays are zeroed. On failure the mesh is left empty and err names `name`. */
bool sl_scene_mesh_alloc(sl_mesh *mesh, int vertex_count, int triangle_count, bool with_texcoords, const char *name,
                      sl_error *err);

/* Angle-weighted vertex normals. Vertices sharing a `group` value (e.g. the OBJ position a
 * vertex was made from, so that texture seams do not split the shading) accumulate together;
 * group == NULL means each vertex is its own group (group_count is then ignored). Vertices
 * with keep[v] true keep their normal; keep == NULL recomputes all. Never writes NaN:
 * a vertex whose accumulated normal is zero or not finite gets +Z. Returns false only when
 * the scratch allocation fails (normals are then untouched). */
bool sl_scene_compute_normals(sl_mesh *mesh, const uint32_t *group, uint32_t group_count, const bool *keep);

/* Tangents (xyz unit, orthogonal to the normal; w = +-1) from positions, texture coordinates and
 * the normals already computed; nothing to do without texture coordinates. Returns false only
 * when the scratch allocation fails. */
bool sl_scene_compute_tangents(sl_mesh *mesh);

/* Unit vector along v, robust to huge and tiny components; false when v is zero or not finite. */
bool sl_scene_safe_normalize(vec3 v, vec3 *out);
/* After a material's keys or a model's material are read: a metallic material without per-texel
 * inputs folded into constant kd, ks; `textured` set from its maps and extra channels (scene_materials.c). */
void sl_scene_material_finish(sl_material *m);

/* The first camera of the models a scene loads (model_scene.c), for the default scene. */
typedef struct {
    bool has;
    sl_camera camera;
} scene_model_camera;

/* Replace each object whose mesh is a model by one object per mesh instance of the file, adding
 * its meshes and materials; `material_given[o]`: object o named a material, which overrides
 * the file's; `first_user[mesh]` names the object in messages, prefixed by `name` (NULL: a model
 * given alone, whose own messages name it); the first model camera goes into `camera` (may be
 * NULL) (model_scene.c). */
bool sl_scene_expand_models(sl_scene *scene, const bool *material_given, const int *first_user, const char *name,
                         scene_model_camera *camera, sl_error *err);

/* The file a model's texture reference `ref` names, relative to the model's folder `dir` ("" or
 * ending in '/'): Windows separators, Blender's "//", case differences and foreign absolute paths
 * resolved as texture_path.c describes. False when no regular file matches. */
bool sl_scene_texture_path_resolve(const char *dir, const char *ref, char out[SL_PATH_MAX]);

/* The plain-text formats' checks before the importer reads them (text_model_check.c): an OBJ's
 * usemtl names each defined by a newmtl of the libraries it names (found relative to `dir`; NULL:
 * none can be read, the file is in memory), an
 * OFF file's counts within the caps and its faces' indices within its vertices. */
bool sl_scene_obj_check(const char *text, size_t size, const char *dir, const char *name, sl_error *err);
bool sl_scene_off_check(const char *text, size_t size, const char *name, sl_error *err);

/* What a glTF document's checks learn for the import: the bytes its buffers declare (for the
 * import's memory budget) and the triangles its triangle lists declare (-1 when it has other
 * primitives), to find the ones the importer drops. */
typedef struct {
    size_t buffer_bytes;
    long long triangles;
} scene_gltf_facts;

/* A glTF document's checks before the importer reads it (gltf_check.c): the .glb container when
 * `glb`, then the caps, the JSON types of nodes, materials and accessors with the JSON path, the
 * node graph and the triangle lists' counts. `facts` may be NULL. */
bool sl_scene_gltf_check(const unsigned char *bytes, size_t size, bool glb, const char *name, scene_gltf_facts *facts,
                      sl_error *err);

/* An import function run by sl_scene_import_isolated: fills *model or *err. */
typedef bool (*scene_import_fn)(void *ctx, sl_model *model, sl_error *err);
/* Runs fn in a child process whose address space may grow by `memory_bytes` and which may run
 * `seconds`, and returns its model or error; running out of either, or crashing, is an error
 * naming `name`, with *model zeroed (model_isolate.c). */
bool sl_scene_import_isolated(scene_import_fn fn, void *ctx, const char *name, size_t memory_bytes, int seconds,
                           sl_model *model, sl_error *err);

#endif
