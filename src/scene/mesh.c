/* mesh.c - sl_mesh storage, validation, angle-weighted normals and generated tangents.
 *
 * Everything that builds a mesh (obj.c, shapes.c) allocates through sl_scene_mesh_alloc and
 * fills normals through sl_scene_compute_normals, so a mesh leaving src/scene always has unit,
 * finite normals and in-range indices; sl_mesh_validate checks exactly that contract. A mesh
 * with texture coordinates also has tangents (analytic for the shapes, sl_scene_compute_tangents
 * otherwise): a normal map needs them, and computing them once per mesh is cheaper than per
 * fragment. */
#include "scene_internal.h"

#include <stdlib.h>
#include <string.h>

/* Normals a validated mesh may carry: unit length within this tolerance (float rounding of a
 * normalisation is ~1e-7; anything beyond 1e-3 means the normal was never normalised). */
#define NORMAL_LENGTH_TOLERANCE 1e-3f

void sl_mesh_free(sl_mesh *mesh)
{
    if (!mesh)
        return;
    free(mesh->positions);
    free(mesh->normals);
    free(mesh->texcoords);
    free(mesh->tangents);
    free(mesh->indices);
    memset(mesh, 0, sizeof *mesh);
}

bool sl_scene_mesh_alloc(sl_mesh *mesh, int vertex_count, int triangle_count, bool with_texcoords, const char *name,
                      sl_error *err)
{
    memset(mesh, 0, sizeof *mesh);
    if (vertex_count < 0 || vertex_count > SCENE_MAX_VERTICES)
        return sl_fail(err, SL_ERR_RANGE, "%s: %d vertices is outside 0..%d", name, vertex_count,
                       SCENE_MAX_VERTICES);
    if (triangle_count < 0 || triangle_count > SCENE_MAX_TRIANGLES)
        return sl_fail(err, SL_ERR_RANGE, "%s: %d triangles is outside 0..%d", name, triangle_count,
                       SCENE_MAX_TRIANGLES);
    size_t nv = (size_t)vertex_count, nt = (size_t)triangle_count;
    /* calloc(0) may return NULL legitimately: ask for at least one element. */
    mesh->positions = calloc(nv ? nv : 1, sizeof(vec3));
    mesh->normals = calloc(nv ? nv : 1, sizeof(vec3));
    mesh->indices = calloc(nt ? 3 * nt : 1, sizeof(uint32_t));
    if (with_texcoords) {
        mesh->texcoords = calloc(nv ? nv : 1, sizeof(vec2));
        mesh->tangents = calloc(nv ? nv : 1, sizeof(vec4));
    }
    if (!mesh->positions || !mesh->normals || !mesh->indices ||
        (with_texcoords && (!mesh->texcoords || !mesh->tangents))) {
        sl_mesh_free(mesh);
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for %d vertices and %d triangles", name,
                       vertex_count, triangle_count);
    }
    mesh->vertex_count = vertex_count;
    mesh->triangle_count = triangle_count;
    return true;
}

bool sl_scene_safe_normalize(vec3 v, vec3 *out)
{
    /* Scale by the largest component first so that squaring neither overflows (1e30) nor
     * underflows (1e-30) before the square root. */
    float m = maxf(fabsf(v.x), maxf(fabsf(v.y), fabsf(v.z)));
    if (!(m > 0.0f) || !isfinite(m))
        return false;
    vec3 s = scale3(v, 1.0f / m);
    float len = length3(s);
    if (!(len > 0.0f) || !isfinite(len))
        return false;
    *out = scale3(s, 1.0f / len);
    return true;
}

bool sl_scene_compute_normals(sl_mesh *mesh, const uint32_t *group, uint32_t group_count, const bool *keep)
{
    size_t slots = group ? (size_t)group_count : (size_t)mesh->vertex_count;
    vec3 *acc = calloc(slots ? slots : 1, sizeof *acc);
    if (!acc)
        return false;
    for (int t = 0; t < mesh->triangle_count; t++) {
        const uint32_t *tri = &mesh->indices[3 * (size_t)t];
        vec3 p[3] = {mesh->positions[tri[0]], mesh->positions[tri[1]], mesh->positions[tri[2]]};
        vec3 face;
        if (!sl_scene_safe_normalize(cross(sub3(p[1], p[0]), sub3(p[2], p[0])), &face))
            continue; /* degenerate triangle: no direction to contribute */
        for (int k = 0; k < 3; k++) {
            /* The corner's angle, from unit edges so huge coordinates cannot overflow;
             * atan2 of |cross| and dot is accurate for angles near 0 and pi, unlike acos. */
            vec3 e1, e2;
            if (!sl_scene_safe_normalize(sub3(p[(k + 1) % 3], p[k]), &e1) ||
                !sl_scene_safe_normalize(sub3(p[(k + 2) % 3], p[k]), &e2))
                continue;
            float angle = atan2f(length3(cross(e1, e2)), dot3(e1, e2));
            uint32_t slot = group ? group[tri[k]] : tri[k];
            acc[slot] = add3(acc[slot], scale3(face, angle));
        }
    }
    for (int v = 0; v < mesh->vertex_count; v++) {
        if (keep && keep[v])
            continue;
        vec3 n;
        if (!sl_scene_safe_normalize(acc[group ? group[v] : (uint32_t)v], &n))
            n = vec3(0.0f, 0.0f, 1.0f); /* unreferenced, degenerate or cancelling faces */
        mesh->normals[v] = n;
    }
    free(acc);
    return true;
}

/* Any unit vector orthogonal to the unit vector n (a tangent where the UVs say nothing). */
static vec3 any_orthogonal(vec3 n)
{
    vec3 axis = fabsf(n.x) < 0.9f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f);
    vec3 t;
    if (!sl_scene_safe_normalize(sub3(axis, scale3(n, dot3(n, axis))), &t))
        t = vec3(1.0f, 0.0f, 0.0f);
    return t;
}

/* Lengyel's method ("Computing Tangent Space Basis Vectors for an Arbitrary Mesh", 2001): per
 * triangle, solve the edges e1 = du1 T + dv1 B, e2 = du2 T + dv2 B for the directions T = dP/du and
 * B = dP/dv; sum them per vertex; then per vertex orthogonalise T against the normal
 * (Gram-Schmidt) and take w = sign(dot(cross(N, T), B)). Each triangle's T and B are normalised
 * and weighted by the corner's angle, the weighting of the normals above and of MikkTSpace.
 * Where it differs from MikkTSpace (what glTF assets are baked against): MikkTSpace also splits a
 * vertex whose triangles disagree in handedness (mirrored UVs sharing a vertex) and keeps the
 * unorthogonalised bitangent magnitude; here such a vertex gets one averaged frame. On meshes
 * split at UV seams and mirrors (what the OBJ reader makes: a vertex per (v, vt, vn)) the two
 * agree up to float rounding for planar and smooth, non-mirrored charts. */
bool sl_scene_compute_tangents(sl_mesh *mesh)
{
    if (!mesh->texcoords || !mesh->tangents)
        return true;
    size_t nv = (size_t)mesh->vertex_count;
    vec3 *acc = calloc(nv ? 2 * nv : 1, sizeof *acc);
    if (!acc)
        return false;
    vec3 *tacc = acc, *bacc = acc + nv;
    for (int t = 0; t < mesh->triangle_count; t++) {
        const uint32_t *tri = &mesh->indices[3 * (size_t)t];
        vec3 p[3] = {mesh->positions[tri[0]], mesh->positions[tri[1]], mesh->positions[tri[2]]};
        vec2 w[3] = {mesh->texcoords[tri[0]], mesh->texcoords[tri[1]], mesh->texcoords[tri[2]]};
        vec3 e1 = sub3(p[1], p[0]), e2 = sub3(p[2], p[0]);
        float du1 = w[1].x - w[0].x, dv1 = w[1].y - w[0].y;
        float du2 = w[2].x - w[0].x, dv2 = w[2].y - w[0].y;
        float det = du1 * dv2 - du2 * dv1;
        if (!(fabsf(det) > 0.0f) || !isfinite(det))
            continue; /* the UVs of this triangle are degenerate: it says nothing about T */
        vec3 tdir, bdir;
        /* T = (dv2 e1 - dv1 e2) / det, B = (du1 e2 - du2 e1) / det; normalised, so 1/det is only
         * its sign. */
        float sgn = det > 0.0f ? 1.0f : -1.0f;
        if (!sl_scene_safe_normalize(scale3(sub3(scale3(e1, dv2), scale3(e2, dv1)), sgn), &tdir) ||
            !sl_scene_safe_normalize(scale3(sub3(scale3(e2, du1), scale3(e1, du2)), sgn), &bdir))
            continue;
        for (int k = 0; k < 3; k++) {
            vec3 a, b;
            if (!sl_scene_safe_normalize(sub3(p[(k + 1) % 3], p[k]), &a) ||
                !sl_scene_safe_normalize(sub3(p[(k + 2) % 3], p[k]), &b))
                continue;
            float angle = atan2f(length3(cross(a, b)), dot3(a, b));
            tacc[tri[k]] = add3(tacc[tri[k]], scale3(tdir, angle));
            bacc[tri[k]] = add3(bacc[tri[k]], scale3(bdir, angle));
        }
    }
    for (size_t v = 0; v < nv; v++) {
        vec3 n = mesh->normals[v], t;
        if (!sl_scene_safe_normalize(sub3(tacc[v], scale3(n, dot3(n, tacc[v]))), &t))
            t = any_orthogonal(n);
        float w = dot3(cross(n, t), bacc[v]) < 0.0f ? -1.0f : 1.0f;
        mesh->tangents[v] = vec4(t.x, t.y, t.z, w);
    }
    free(acc);
    return true;
}

void sl_mesh_compute_normals(sl_mesh *mesh)
{
    if (!mesh || !mesh->normals)
        return;
    if (!sl_scene_compute_normals(mesh, NULL, 0, NULL)) {
        /* Out of memory for the scratch: still honour "never NaN, always unit". */
        for (int v = 0; v < mesh->vertex_count; v++)
            mesh->normals[v] = vec3(0.0f, 0.0f, 1.0f);
    }
}

static bool finite3(vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

bool sl_mesh_validate(const sl_mesh *mesh, const char *name, sl_error *err)
{
    if (!name)
        name = "mesh";
    if (mesh->vertex_count < 0 || mesh->triangle_count < 0)
        return sl_fail(err, SL_ERR_FORMAT, "%s: negative counts (%d vertices, %d triangles)", name,
                       mesh->vertex_count, mesh->triangle_count);
    if (mesh->vertex_count > SCENE_MAX_VERTICES || mesh->triangle_count > SCENE_MAX_TRIANGLES)
        return sl_fail(err, SL_ERR_RANGE, "%s: %d vertices / %d triangles exceed the caps %d / %d", name,
                       mesh->vertex_count, mesh->triangle_count, SCENE_MAX_VERTICES, SCENE_MAX_TRIANGLES);
    if ((mesh->vertex_count > 0 && (!mesh->positions || !mesh->normals)) || (!mesh->texcoords != !mesh->tangents) ||
        (mesh->triangle_count > 0 && !mesh->indices))
        return sl_fail(err, SL_ERR_FORMAT, "%s: missing vertex or index arrays", name);
    for (int v = 0; v < mesh->vertex_count; v++) {
        if (!finite3(mesh->positions[v]))
            return sl_fail(err, SL_ERR_FORMAT, "%s: vertex %d: position is not finite", name, v);
        vec3 n = mesh->normals[v];
        if (!finite3(n))
            return sl_fail(err, SL_ERR_FORMAT, "%s: vertex %d: normal is not finite", name, v);
        float len = length3(n);
        if (!(fabsf(len - 1.0f) <= NORMAL_LENGTH_TOLERANCE))
            return sl_fail(err, SL_ERR_FORMAT, "%s: vertex %d: normal has length %g, not 1", name, v,
                           (double)len);
        if (mesh->texcoords && !(isfinite(mesh->texcoords[v].x) && isfinite(mesh->texcoords[v].y)))
            return sl_fail(err, SL_ERR_FORMAT, "%s: vertex %d: texture coordinate is not finite", name, v);
        if (mesh->tangents) {
            vec4 t = mesh->tangents[v];
            float tl = length3(vec3(t.x, t.y, t.z));
            if (!(fabsf(tl - 1.0f) <= NORMAL_LENGTH_TOLERANCE) || !(t.w == 1.0f || t.w == -1.0f))
                return sl_fail(err, SL_ERR_FORMAT, "%s: vertex %d: tangent has length %g and w %g, not 1 and +-1",
                               name, v, (double)tl, (double)t.w);
        }
    }
    for (int t = 0; t < mesh->triangle_count; t++) {
        for (int k = 0; k < 3; k++) {
            uint32_t i = mesh->indices[3 * (size_t)t + (size_t)k];
            if (i >= (uint32_t)mesh->vertex_count)
                return sl_fail(err, SL_ERR_FORMAT, "%s: triangle %d: index %u out of range (0..%d)", name, t, i,
                               mesh->vertex_count - 1);
        }
    }
    return true;
}
