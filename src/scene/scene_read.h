/* scene_read.h - what the files reading a scene file share (not part of the public API): the
 * reader's state, the typed JSON readers that name the JSON path of what they read, and each
 * section's reader. scene.c reads the document and calls the sections in order.
 *
 *   scene_json.c        the typed readers, JSON paths and messages
 *   scene_json_scan.c   what cJSON does not say: nesting past its limit, U+0000 in a string
 *   scene_camera.c      "camera"
 *   scene_environment.c "environment"
 *   scene_materials.c   "materials" and their texture maps
 *   scene_objects.c     "objects": shapes, OBJ meshes and models, transforms, one mesh per source
 *   scene_lights.c      "lights"
 *   scene_options.c     "render" and every option's key (core/options.h)
 *   scene_default.c     the default scene around a model given alone */
#ifndef SL_SCENE_READ_H
#define SL_SCENE_READ_H

#include <cjson/cJSON.h>

#include "scene_internal.h"

/* The longest JSON path a message shows; a longer one ends in "...". */
#define JSON_PATH_MAX 256
/* Bytes of a key or string from the file that a message shows (sl_scene_masked). */
#define MASKED_MAX 64
/* The name of the material an object without one gets (a scene's own, or a built-in grey). */
#define DEFAULT_MATERIAL_NAME "default"

typedef struct {
    const char *name;     /* the scene's name in messages */
    const char *base_dir; /* for relative paths; "" = as given */
    sl_error *err;
    scene_model_camera *model_camera; /* the models' first camera, for the default scene; may be NULL */
    const sl_option_values *given;    /* the command line's record (sl_scene_load_with); NULL: none */
} scene_parser;

/* What a model loaded for this parser does with a texture that names no file: the command line's
 * choice when it gave one, else `own` (the object's key, or the default). */
sl_missing_textures sl_scene_missing_textures(const scene_parser *p, sl_missing_textures own);

/* ---- scene_json.c: errors, JSON paths and typed readers ---- */

/* "NAME: PATH: message" (no path at the top level) into p->err; returns false. */
bool sl_scene_fail(scene_parser *p, const char *path, sl_error_code code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
/* Up to `max` (at most MASKED_MAX) bytes of `s` for a message, each byte that is not printable
 * ASCII shown as '?', "..." after a longer one. */
const char *sl_scene_masked(const char *s, size_t max, char out[MASKED_MAX + 4]);
void sl_scene_join_key(char *out, const char *path, const char *key); /* "path.key" */
void sl_scene_join_index(char *out, const char *path, int i);         /* "path[i]" */
const cJSON *sl_scene_member(const cJSON *obj, const char *key);
/* A "comment": a string or an array of strings. */
bool sl_scene_comment_ok(const cJSON *item);
/* `item` must be an object whose keys are all in `allowed` (plus "comment"), none repeated. */
bool sl_scene_check_keys(scene_parser *p, const cJSON *item, const char *path, const char *const allowed[]);
/* Each checks the JSON type and range of one value and names `path` when it fails. */
bool sl_scene_read_number(scene_parser *p, const cJSON *item, const char *path, double *out);
bool sl_scene_read_float(scene_parser *p, const cJSON *item, const char *path, double lo, double hi, float *out);
bool sl_scene_read_int(scene_parser *p, const cJSON *item, const char *path, int lo, int hi, int *out);
bool sl_scene_read_numbers(scene_parser *p, const cJSON *item, const char *path, int n, double *out);
bool sl_scene_read_vec3(scene_parser *p, const cJSON *item, const char *path, vec3 *out);
bool sl_scene_read_color(scene_parser *p, const cJSON *item, const char *path, double hi, vec3 *out);
bool sl_scene_check_no_control(scene_parser *p, const char *s, const char *path);
bool sl_scene_read_string(scene_parser *p, const cJSON *item, const char *path, char *out, size_t cap);
/* A file path, resolved relative to the scene file's folder. */
bool sl_scene_read_path(scene_parser *p, const cJSON *item, const char *path, char out[SL_PATH_MAX]);
/* Line and column (1-based) of a byte offset. */
void sl_scene_line_column(const char *text, size_t offset, size_t *line, size_t *column);

/* ---- scene_json_scan.c ---- */

/* Walks the JSON text [0, end) for an array or object nested deeper than cJSON reads (when
 * `depth`) or a string holding \u0000 (when `nul`); false with the error's line, column and path. */
bool sl_scene_scan_json(scene_parser *p, const char *text, size_t end, bool depth, bool nul);

/* ---- the sections; each item may be NULL (the section is absent: its defaults) ---- */

bool sl_scene_parse_camera(scene_parser *p, const cJSON *item, sl_camera *cam);
bool sl_scene_parse_environment(scene_parser *p, const cJSON *item, sl_environment_desc *env, sl_option_values *options);
bool sl_scene_parse_lights(scene_parser *p, const cJSON *item, sl_scene *scene);
/* The option `id` at its key(s) in `section` (the object its scene key's first word names), held
 * to the range the declaration gives scene files, into `options`, marked as given. */
bool sl_scene_read_option(scene_parser *p, const cJSON *section, sl_option_id id, sl_option_values *options);
bool sl_scene_parse_render(scene_parser *p, const cJSON *item, sl_option_values *options);

/* A material name and its index, sorted by name for duplicate checks and lookups. */
typedef struct {
    const char *name;
    int index;
} scene_name_index;
/* Materials; `sorted` gets them ordered by name. The array has room for one more, the implicit
 * default material. */
bool sl_scene_parse_materials(scene_parser *p, const cJSON *item, sl_scene *scene, scene_name_index **sorted);
int sl_scene_find_material(const scene_name_index *sorted, int count, const char *name); /* -1: none */
sl_material sl_scene_default_material(const char *name);
/* The map keys ("kd_map", ...) by slot, for messages. */
extern const char *const sl_scene_map_keys[SL_MAP_COUNT];

/* The distinct mesh sources seen so far, hashed (open addressing, at most half full: sized
 * for every object naming its own source), so that finding an object's mesh costs O(1), not
 * a scan of every mesh before it. */
typedef struct {
    int *slots; /* mesh index + 1; 0 = empty */
    size_t mask;
} scene_source_map;
bool sl_scene_source_map_init(scene_source_map *map, size_t sources);
bool sl_scene_parse_object(scene_parser *p, const cJSON *item, const char *path, sl_scene *scene,
                        const scene_name_index *sorted, int named_materials, scene_source_map *sources, int *first_user,
                        sl_object *obj, bool *material_given);
/* The object's default name: the mesh file's base name without extension, or the shape. */
void sl_scene_default_object_name(char out[SL_NAME_MAX], const char *mesh_text, const char *shape);
/* Build every distinct mesh (a model's: sl_scene_expand_models); `first_user[mesh]` names the
 * object in messages. */
bool sl_scene_load_meshes(scene_parser *p, sl_scene *scene, const int *first_user);
/* A material with maps needs texture coordinates on every mesh it is drawn on. */
bool sl_scene_check_maps_have_uvs(scene_parser *p, const sl_scene *scene);

/* ---- scene_default.c ---- */

/* The default scene around a model file given alone (docs/scene-format.md "Models"). */
bool sl_scene_load_model_alone(const char *path, const sl_option_values *given, sl_scene *scene, sl_error *err);

#endif
