/* shapes.c - the built-in shapes a scene can name without an OBJ file: sphere, plane, box.
 *
 * All are unit sized and centred at the origin in a Z-up object space, with counter-
 * clockwise front faces seen from outside (OpenGL's default glFrontFace(GL_CCW)), so the
 * cross product of a triangle's edges (b - a) x (c - a) points along its vertex normals.
 * Texture coordinates span [0,1]^2 per shape (per face for the box), with analytic tangents:
 * xyz = normalize(dP/du), w = the sign that makes cross(N, T) * w point along dP/dv (glTF). */
#include "scene_internal.h"

#include <string.h>

bool sl_mesh_sphere(sl_mesh *mesh, int slices, int stacks, sl_error *err)
{
    if (slices < 3 || slices > SCENE_SPHERE_MAX_SLICES || stacks < 2 || stacks > SCENE_SPHERE_MAX_STACKS) {
        memset(mesh, 0, sizeof *mesh); /* an output, as sl_scene_mesh_alloc treats it: nothing to free */
        return sl_fail(err, SL_ERR_RANGE, "sphere: %d slices x %d stacks is outside 3..%d x 2..%d", slices, stacks,
                       SCENE_SPHERE_MAX_SLICES, SCENE_SPHERE_MAX_STACKS);
    }
    /* A (stacks+1) x (slices+1) grid: row i at polar angle theta = pi i / stacks from +Z, column j
     * at azimuth phi = 2 pi j / slices. The last column repeats the first (u = 1 vs u = 0) and
     * the pole rows repeat their point, so texture coordinates stay continuous. The quads
     * touching a pole are single triangles (the other half would be degenerate). */
    int vertex_count = (stacks + 1) * (slices + 1);
    int triangle_count = 2 * slices * (stacks - 1);
    if (!sl_scene_mesh_alloc(mesh, vertex_count, triangle_count, true, "sphere", err))
        return false;
    for (int i = 0; i <= stacks; i++) {
        float theta = SL_PI * (float)i / (float)stacks;
        /* Exact poles: sinf(pi) is 8.7e-8, not 0. */
        float st = (i == 0 || i == stacks) ? 0.0f : sinf(theta);
        float ct = i == 0 ? 1.0f : (i == stacks ? -1.0f : cosf(theta));
        for (int j = 0; j <= slices; j++) {
            float phi = 2.0f * SL_PI * (float)(j % slices) / (float)slices;
            vec3 p = vec3(st * cosf(phi), st * sinf(phi), ct);
            int v = i * (slices + 1) + j;
            mesh->positions[v] = p;
            mesh->normals[v] = p; /* unit sphere: the normal is the position */
            mesh->texcoords[v] = vec2((float)j / (float)slices, (float)i / (float)stacks);
            /* dP/du is along the parallel, (-sin phi, cos phi, 0), defined at the poles too; v grows
             * with theta (downwards, toward -Z) while cross(N, T) points up the meridian: w = -1. */
            mesh->tangents[v] = vec4(-sinf(phi), cosf(phi), 0.0f, -1.0f);
        }
    }
    /* Seen from outside, phi grows to the right and theta downwards, so for the quad with
     * top-left a = (i, j), top-right b = (i, j+1), bottom-left c = (i+1, j), bottom-right
     * d = (i+1, j+1) the counter-clockwise triangles are (a, c, d) and (a, d, b). */
    uint32_t *out = mesh->indices;
    for (int i = 0; i < stacks; i++) {
        for (int j = 0; j < slices; j++) {
            uint32_t a = (uint32_t)(i * (slices + 1) + j), b = a + 1;
            uint32_t c = a + (uint32_t)(slices + 1), d = c + 1;
            if (i != stacks - 1) {
                *out++ = a, *out++ = c, *out++ = d;
            }
            if (i != 0) {
                *out++ = a, *out++ = d, *out++ = b;
            }
        }
    }
    return true;
}

bool sl_mesh_plane(sl_mesh *mesh, sl_error *err)
{
    if (!sl_scene_mesh_alloc(mesh, 4, 2, true, "plane", err))
        return false;
    static const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int v = 0; v < 4; v++) {
        mesh->positions[v] = vec3(corners[v][0], corners[v][1], 0.0f);
        mesh->normals[v] = vec3(0.0f, 0.0f, 1.0f);
        mesh->texcoords[v] = vec2(0.5f * (corners[v][0] + 1.0f), 0.5f * (corners[v][1] + 1.0f));
        mesh->tangents[v] = vec4(1.0f, 0.0f, 0.0f, 1.0f); /* u along +X, v along +Y = cross(+Z, +X) */
    }
    static const uint32_t tris[6] = {0, 1, 2, 0, 2, 3};
    for (int k = 0; k < 6; k++)
        mesh->indices[k] = tris[k];
    return true;
}

bool sl_mesh_box(sl_mesh *mesh, sl_error *err)
{
    if (!sl_scene_mesh_alloc(mesh, 24, 12, true, "box", err))
        return false;
    /* Each face: outward normal n and in-face axes u, v with u x v = n, so the corners
     * n - u - v, n + u - v, n + u + v, n - u + v run counter-clockwise seen from outside. */
    static const float faces[6][3][3] = {
        {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},   {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},   {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
    };
    static const float su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
    for (int f = 0; f < 6; f++) {
        vec3 n = vec3(faces[f][0][0], faces[f][0][1], faces[f][0][2]);
        vec3 u = vec3(faces[f][1][0], faces[f][1][1], faces[f][1][2]);
        vec3 v = vec3(faces[f][2][0], faces[f][2][1], faces[f][2][2]);
        for (int k = 0; k < 4; k++) {
            int i = 4 * f + k;
            mesh->positions[i] = add3(n, add3(scale3(u, su[k]), scale3(v, sv[k])));
            mesh->normals[i] = n;
            mesh->texcoords[i] = vec2(0.5f * (su[k] + 1.0f), 0.5f * (sv[k] + 1.0f));
            /* u runs along the face's u axis, v along its v = cross(n, u) (u x v = n): w = +1 */
            mesh->tangents[i] = vec4(u.x, u.y, u.z, 1.0f);
        }
        uint32_t base = (uint32_t)(4 * f);
        uint32_t *tri = &mesh->indices[6 * f];
        tri[0] = base, tri[1] = base + 1, tri[2] = base + 2;
        tri[3] = base, tri[4] = base + 2, tri[5] = base + 3;
    }
    return true;
}
