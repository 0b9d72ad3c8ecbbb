/* test_shapes.c - the built-in sphere, plane and box (shapes.c): counts, exact positions and
 * normals, counter-clockwise front faces seen from outside, closed surfaces (volume by the
 * divergence theorem), and parameter checks. */
#include "testutil.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene.h"
#include "scene/scene_internal.h" /* sl_scene_compute_tangents */

static const double PI_D = 3.14159265358979323846;

/* Every triangle: (b - a) x (c - a) has a positive component along each of its three vertex
 * normals (front face = counter-clockwise seen from the side the normals point to), and along
 * the direction from the shape's centre (the origin) to the triangle. */
static void assert_ccw_outward(const sl_mesh *m)
{
    for (int t = 0; t < m->triangle_count; t++) {
        const uint32_t *i = &m->indices[3 * t];
        vec3 a = m->positions[i[0]], b = m->positions[i[1]], c = m->positions[i[2]];
        vec3 face = cross(sub3(b, a), sub3(c, a));
        assert_true(length3(face) > 0.0f); /* no degenerate triangles */
        vec3 centroid = scale3(add3(a, add3(b, c)), 1.0f / 3.0f);
        if (!(dot3(face, centroid) > 0.0f)) {
            print_error("triangle %d faces inwards\n", t);
            fail();
        }
        for (int k = 0; k < 3; k++) {
            if (!(dot3(face, m->normals[i[k]]) > 0.0f)) {
                print_error("triangle %d: winding disagrees with the normal of vertex %u\n", t, i[k]);
                fail();
            }
        }
    }
}

/* Signed volume, sum of a . (b x c) / 6: positive for a closed outward-facing surface. */
static double signed_volume(const sl_mesh *m)
{
    double v = 0.0;
    for (int t = 0; t < m->triangle_count; t++) {
        const uint32_t *i = &m->indices[3 * t];
        v += (double)dot3(m->positions[i[0]], cross(m->positions[i[1]], m->positions[i[2]])) / 6.0;
    }
    return v;
}

static void test_sphere(void **state)
{
    (void)state;
    sl_mesh m;
    sl_error err = {0};
    assert_true(sl_mesh_sphere(&m, 16, 8, &err));
    assert_true(sl_mesh_validate(&m, "sphere", &err));
    /* (stacks + 1) rows of (slices + 1) vertices; 2 triangles per quad except at the poles. */
    assert_int_equal(m.vertex_count, 9 * 17);
    assert_int_equal(m.triangle_count, 2 * 16 * 7);
    assert_non_null(m.texcoords);
    for (int v = 0; v < m.vertex_count; v++) {
        assert_near(length3(m.positions[v]), 1.0f, 1e-6f);
        assert_near(dot3(m.normals[v], m.positions[v]), 1.0f, 1e-6f); /* normal = position */
        assert_true(m.texcoords[v].x >= 0.0f && m.texcoords[v].x <= 1.0f);
    }
    /* Poles exactly on +-Z: first row north, last row south. */
    assert_near(m.positions[0].z, 1.0f, 0.0f);
    assert_near(m.positions[0].x, 0.0f, 0.0f);
    assert_near(m.positions[m.vertex_count - 1].z, -1.0f, 0.0f);
    assert_ccw_outward(&m);
    /* An inscribed polyhedron: volume a little under 4/3 pi; 16 x 8 loses about 7 %. */
    double vol = signed_volume(&m);
    assert_true(vol > 0.9 * 4.0 / 3.0 * PI_D && vol < 4.0 / 3.0 * PI_D);
    sl_mesh_free(&m);

    /* Fine tessellation: within 0.2 % of the sphere's volume. */
    assert_true(sl_mesh_sphere(&m, 128, 64, &err));
    assert_ccw_outward(&m);
    assert_near(signed_volume(&m), 4.0 / 3.0 * PI_D, 0.002 * 4.0 / 3.0 * PI_D);
    sl_mesh_free(&m);

    /* The smallest sphere is a closed, correctly wound double pyramid. */
    assert_true(sl_mesh_sphere(&m, 3, 2, &err));
    assert_int_equal(m.triangle_count, 6);
    assert_ccw_outward(&m);
    sl_mesh_free(&m);
}

static void test_sphere_limits(void **state)
{
    (void)state;
    sl_mesh m;
    sl_error err = {0};
    assert_false(sl_mesh_sphere(&m, 2, 8, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_non_null(strstr(err.msg, "sphere: 2 slices"));
    assert_false(sl_mesh_sphere(&m, 16, 1, &err));
    assert_false(sl_mesh_sphere(&m, 1025, 8, &err));
    assert_false(sl_mesh_sphere(&m, 16, 513, &err));
    assert_null(m.positions);
}

static void test_plane(void **state)
{
    (void)state;
    sl_mesh m;
    sl_error err = {0};
    assert_true(sl_mesh_plane(&m, &err));
    assert_true(sl_mesh_validate(&m, "plane", &err));
    assert_int_equal(m.vertex_count, 4);
    assert_int_equal(m.triangle_count, 2);
    for (int v = 0; v < 4; v++) {
        assert_near(fabsf(m.positions[v].x), 1.0f, 0.0f);
        assert_near(fabsf(m.positions[v].y), 1.0f, 0.0f);
        assert_near(m.positions[v].z, 0.0f, 0.0f);
        assert_near(m.normals[v].z, 1.0f, 0.0f);
    }
    /* Counter-clockwise seen from +Z, and the two triangles cover area 4. */
    float area = 0.0f;
    for (int t = 0; t < 2; t++) {
        const uint32_t *i = &m.indices[3 * t];
        vec3 face = cross(sub3(m.positions[i[1]], m.positions[i[0]]), sub3(m.positions[i[2]], m.positions[i[0]]));
        assert_true(face.z > 0.0f);
        area += 0.5f * face.z;
    }
    assert_near(area, 4.0f, 0.0f);
    sl_mesh_free(&m);
}

static void test_box(void **state)
{
    (void)state;
    sl_mesh m;
    sl_error err = {0};
    assert_true(sl_mesh_box(&m, &err));
    assert_true(sl_mesh_validate(&m, "box", &err));
    assert_int_equal(m.vertex_count, 24);
    assert_int_equal(m.triangle_count, 12);
    int per_axis[3][2] = {{0, 0}, {0, 0}, {0, 0}};
    for (int v = 0; v < 24; v++) {
        vec3 p = m.positions[v], n = m.normals[v];
        assert_near(fabsf(p.x), 1.0f, 0.0f);
        assert_near(fabsf(p.y), 1.0f, 0.0f);
        assert_near(fabsf(p.z), 1.0f, 0.0f);
        /* Flat normals: a unit axis, and the vertex lies on that face (p . n = 1). */
        assert_near(fabsf(n.x) + fabsf(n.y) + fabsf(n.z), 1.0f, 0.0f);
        assert_near(dot3(p, n), 1.0f, 0.0f);
        int axis = n.x != 0.0f ? 0 : (n.y != 0.0f ? 1 : 2);
        per_axis[axis][dot3(n, vec3s(1.0f)) > 0.0f]++;
    }
    for (int a = 0; a < 3; a++)
        for (int s = 0; s < 2; s++)
            assert_int_equal(per_axis[a][s], 4); /* 4 vertices on each of the 6 faces */
    assert_ccw_outward(&m);
    assert_near(signed_volume(&m), 8.0, 1e-9);
    sl_mesh_free(&m);
}

/* Each triangle's own frame from its positions and UVs: T = dP/du, B = dP/dv (solved from two edges),
 * normalised. Every vertex's tangent must agree with T in direction, and cross(N, T) * w with B in
 * sign: what a normal map's +X and +Y (OpenGL, glTF) are relative to the surface. */
static void assert_tangents_follow_uv(const sl_mesh *m, float min_dot)
{
    assert_non_null(m->tangents);
    for (int t = 0; t < m->triangle_count; t++) {
        const uint32_t *i = &m->indices[3 * t];
        vec3 e1 = sub3(m->positions[i[1]], m->positions[i[0]]), e2 = sub3(m->positions[i[2]], m->positions[i[0]]);
        vec2 w0 = m->texcoords[i[0]], w1 = m->texcoords[i[1]], w2 = m->texcoords[i[2]];
        float du1 = w1.x - w0.x, dv1 = w1.y - w0.y, du2 = w2.x - w0.x, dv2 = w2.y - w0.y;
        float det = du1 * dv2 - du2 * dv1;
        assert_true(det != 0.0f);
        vec3 T = normalize(scale3(sub3(scale3(e1, dv2), scale3(e2, dv1)), 1.0f / det));
        vec3 B = normalize(scale3(sub3(scale3(e2, du1), scale3(e1, du2)), 1.0f / det));
        for (int k = 0; k < 3; k++) {
            vec4 tv = m->tangents[i[k]];
            vec3 tx = vec3(tv.x, tv.y, tv.z);
            assert_near(length3(tx), 1.0f, 1e-5f);
            assert_near(dot3(tx, m->normals[i[k]]), 0.0f, 1e-5f);
            if (dot3(tx, T) < min_dot || dot3(scale3(cross(m->normals[i[k]], tx), tv.w), B) < min_dot) {
                print_error("triangle %d vertex %u: T.t = %g, B.b = %g\n", t, i[k], (double)dot3(tx, T),
                            (double)dot3(scale3(cross(m->normals[i[k]], tx), tv.w), B));
                fail();
            }
        }
    }
}

/* The shapes' analytic tangents against the generated ones (Lengyel, mesh.c) on the same mesh:
 * equal within float rounding on the plane and box (flat charts), within the facet angle on the
 * sphere (the generated ones average the facets' dP/du). Handedness equal everywhere. */
static void assert_generated_match(sl_mesh *m, float min_dot)
{
    size_t n = (size_t)m->vertex_count;
    vec4 *analytic = malloc(n * sizeof *analytic);
    assert_non_null(analytic);
    memcpy(analytic, m->tangents, n * sizeof *analytic);
    assert_true(sl_scene_compute_tangents(m));
    bool *used = calloc(n, sizeof *used); /* the sphere's last pole vertex is in no triangle */
    assert_non_null(used);
    for (int k = 0; k < 3 * m->triangle_count; k++)
        used[m->indices[k]] = true;
    for (size_t v = 0; v < n; v++) {
        vec4 a = analytic[v], g = m->tangents[v];
        if (!used[v])
            continue;
        assert_true(a.w == g.w);
        assert_true(a.x * g.x + a.y * g.y + a.z * g.z >= min_dot);
    }
    free(used);
    free(analytic);
}

static void test_tangents(void **state)
{
    (void)state;
    sl_error err = {0};
    sl_mesh m;
    assert_true(sl_mesh_plane(&m, &err));
    assert_tangents_follow_uv(&m, 0.999999f);
    assert_generated_match(&m, 0.999999f);
    sl_mesh_free(&m);
    assert_true(sl_mesh_box(&m, &err));
    assert_tangents_follow_uv(&m, 0.999999f);
    assert_generated_match(&m, 0.999999f);
    sl_mesh_free(&m);
    /* 32 slices: a facet spans 11.25 degrees; a vertex tangent is within half of it of the facet's
     * dP/du (cos 5.625 deg = 0.9952). The pole triangles' dP/dv leans further from the meridian
     * (measured 0.976): 0.97. */
    assert_true(sl_mesh_sphere(&m, 32, 16, &err));
    assert_tangents_follow_uv(&m, 0.97f);
    assert_true(sl_mesh_validate(&m, "sphere", &err));
    assert_generated_match(&m, 0.99f);
    sl_mesh_free(&m);
}

/* Generated tangents on a hand-made quad whose UVs are mirrored (u runs along -X, v along +Y):
 * T = -X, and cross(N, T) = cross(+Z, -X) = -Y points against dP/dv = +Y, so w = -1. */
static void test_tangents_mirrored(void **state)
{
    (void)state;
    static const char obj[] = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                              "vt 1 0\nvt 0 0\nvt 0 1\nvt 1 1\nvn 0 0 1\n"
                              "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n";
    sl_mesh m;
    sl_error err = {0};
    assert_true(sl_mesh_parse_obj(obj, sizeof obj - 1, "mirror.obj", &m, &err));
    assert_true(sl_mesh_validate(&m, "mirror.obj", &err));
    for (int v = 0; v < m.vertex_count; v++) {
        assert_near(m.tangents[v].x, -1.0f, 1e-6f);
        assert_near(m.tangents[v].y, 0.0f, 1e-6f);
        assert_true(m.tangents[v].w == -1.0f);
    }
    sl_mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_sphere_limits),
        cmocka_unit_test(test_plane),
        cmocka_unit_test(test_box),
        cmocka_unit_test(test_tangents),
        cmocka_unit_test(test_tangents_mirrored),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
