/* softlight/scene.h - meshes, the camera, and scenes loaded from files.
 *
 * A scene is a JSON file (docs/scene-format.md) naming meshes (OBJ files, built-in shapes,
 * models imported through assimp: glTF, OBJ, ...), materials, lights, a camera and an
 * environment; a model file given alone becomes the default scene around it. World space is
 * Z-up, right-handed; colours are linear RGB. The loaded scene is opaque: it is rendered
 * (renderer.h) or drawn into a G-buffer (gbuffer.h, sl_raster_scene). */
#ifndef SOFTLIGHT_SCENE_H
#define SOFTLIGHT_SCENE_H

#include <stdbool.h>
#include <stdint.h>

#include <softlight/types.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Triangle mesh in object space: shared vertices, 3 indices per triangle (counter-clockwise
 * front faces). `normals` always present; `texcoords` may be NULL, and `tangents` is present
 * exactly when texcoords is: xyz a unit vector along dP/du orthogonal to the normal, w = +1 or
 * -1 the handedness, as glTF's TANGENT. */
typedef struct sl_mesh {
    int vertex_count, triangle_count;
    sl_vec3 *positions;
    sl_vec3 *normals;
    sl_vec2 *texcoords;
    sl_vec4 *tangents;
    uint32_t *indices;
} sl_mesh;

/* Meshes: an OBJ file, or a built-in shape (unit sized, centred at the origin, texture
 * coordinates in [0,1]^2). `mesh` is an output: its old contents are not freed, and it is all
 * zeros on failure. The sphere has poles on +-Z, `slices` (3..1024) around Z and `stacks`
 * (2..512) from pole to pole. */
SL_API bool sl_mesh_load_obj(const char *path, sl_mesh *mesh, sl_error *err);
SL_API bool sl_mesh_sphere(sl_mesh *mesh, int slices, int stacks, sl_error *err); /* radius 1 */
SL_API bool sl_mesh_plane(sl_mesh *mesh, sl_error *err); /* [-1,1]^2 at z = 0, normal +Z */
SL_API bool sl_mesh_box(sl_mesh *mesh, sl_error *err);   /* [-1,1]^3, flat normals per face */
SL_API void sl_mesh_free(sl_mesh *mesh);

/* A pinhole camera. */
typedef struct sl_camera {
    sl_vec3 eye, target, up;
    float fovy_deg;     /* vertical field of view, degrees */
    float znear, zfar;
} sl_camera;

/* proj * view for a width x height target: view = look-at(eye, target, up), proj =
 * perspective(fovy, width / height, near, far), GL conventions. */
SL_API sl_mat4 sl_camera_view_proj(const sl_camera *cam, int width, int height);

typedef struct sl_scene sl_scene;

/* Load a scene file (.json) or a model file and every mesh it names; NULL (and err, naming the
 * file and the JSON path) on failure. Free with sl_scene_close. */
SL_API sl_scene *sl_scene_open(const char *path, sl_error *err);
SL_API void sl_scene_close(sl_scene *scene); /* NULL is fine */
/* The scene's camera. */
SL_API sl_camera sl_scene_camera(const sl_scene *scene);
/* What loads but is not drawn (model import), one line each ending in "\n"; "" when none. */
SL_API const char *sl_scene_warnings(const sl_scene *scene);
/* World-space bounds of all objects; false when the scene has no geometry. */
SL_API bool sl_scene_bounds(const sl_scene *scene, sl_vec3 *lo, sl_vec3 *hi);

#ifdef __cplusplus
}
#endif

#endif
