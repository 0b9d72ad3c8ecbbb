/* test_obj.c - the OBJ reader (obj.c) and mesh helpers (mesh.c): face forms, indices, fan
 * triangulation, normals (given, computed, angle-weighted, degenerate), errors with line
 * numbers, and the shipped bunny. Expected values are worked out by hand in the comments. */
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene.h"

static void parse_ok(const char *text, sl_mesh *m)
{
    sl_error err = {0};
    if (!sl_mesh_parse_obj(text, strlen(text), "t.obj", m, &err)) {
        print_error("unexpected error: %s\n", err.msg);
        fail();
    }
    assert_true(sl_mesh_validate(m, "t.obj", &err));
}

/* Parse must fail and the message must contain `want`. */
static void parse_fails(const char *text, const char *want)
{
    sl_mesh m;
    sl_error err = {0};
    bool ok = sl_mesh_parse_obj(text, strlen(text), "t.obj", &m, &err);
    if (ok || !strstr(err.msg, want)) {
        print_error("expected an error containing \"%s\", got %s \"%s\"\n", want, ok ? "success" : "error",
                    err.msg);
        sl_mesh_free(&m);
        fail();
    }
    /* A failed parse leaves an empty mesh. */
    assert_int_equal(m.vertex_count, 0);
    assert_null(m.positions);
}

static void assert_vec3_near(vec3 a, vec3 b, float tol)
{
    assert_near(a.x, b.x, tol);
    assert_near(a.y, b.y, tol);
    assert_near(a.z, b.z, tol);
}

static const char *TRI_HEAD = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                              "vt 0 0\nvt 1 0\nvt 0 1\n"
                              "vn 0 0 2\n"; /* not unit: the reader must normalise it */

static void test_face_form_v(void **state)
{
    (void)state;
    char text[256];
    snprintf(text, sizeof text, "%sf 1 2 3\n", TRI_HEAD);
    sl_mesh m;
    parse_ok(text, &m);
    assert_int_equal(m.vertex_count, 3);
    assert_int_equal(m.triangle_count, 1);
    assert_null(m.texcoords); /* no corner named a vt */
    for (int v = 0; v < 3; v++)
        assert_vec3_near(m.normals[v], vec3(0, 0, 1), 0.0f); /* computed: CCW in z = 0 -> +Z exactly */
    assert_vec3_near(m.positions[1], vec3(1, 0, 0), 0.0f);
    sl_mesh_free(&m);
}

static void test_face_form_vt(void **state)
{
    (void)state;
    char text[256];
    snprintf(text, sizeof text, "%sf 1/3 2/2 3/1\n", TRI_HEAD);
    sl_mesh m;
    parse_ok(text, &m);
    assert_int_equal(m.vertex_count, 3);
    assert_non_null(m.texcoords);
    assert_near(m.texcoords[0].x, 0.0f, 0.0f);
    assert_near(m.texcoords[0].y, 1.0f, 0.0f); /* vt 3 */
    assert_near(m.texcoords[1].x, 1.0f, 0.0f); /* vt 2 */
    assert_near(m.texcoords[2].y, 0.0f, 0.0f); /* vt 1 */
    sl_mesh_free(&m);
}

static void test_face_form_vn(void **state)
{
    (void)state;
    char text[256];
    /* The file's normal is +Z*2 for all three; after normalising it is exactly +Z. Use a
     * clockwise triangle so a computed normal (-Z) could not be mistaken for the given one. */
    snprintf(text, sizeof text, "%sf 1//1 3//1 2//1\n", TRI_HEAD);
    sl_mesh m;
    parse_ok(text, &m);
    assert_null(m.texcoords);
    for (int v = 0; v < 3; v++)
        assert_vec3_near(m.normals[v], vec3(0, 0, 1), 0.0f);
    assert_int_equal(m.indices[1], 1);
    assert_vec3_near(m.positions[m.indices[1]], vec3(0, 1, 0), 0.0f);
    sl_mesh_free(&m);
}

static void test_face_form_vtn(void **state)
{
    (void)state;
    char text[256];
    snprintf(text, sizeof text, "%sf 1/1/1 2/2/1 3/3/1\n", TRI_HEAD);
    sl_mesh m;
    parse_ok(text, &m);
    assert_non_null(m.texcoords);
    assert_near(m.texcoords[2].y, 1.0f, 0.0f);
    assert_vec3_near(m.normals[2], vec3(0, 0, 1), 0.0f);
    sl_mesh_free(&m);
}

/* One output vertex per distinct (v, vt, vn): a shared corner is shared, a UV seam splits. */
static void test_unique_vertices(void **state)
{
    (void)state;
    sl_mesh m;
    /* Quad as two triangles sharing positions 1 and 3 with the same vt: 4 vertices. */
    parse_ok("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
             "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n",
             &m);
    assert_int_equal(m.vertex_count, 4);
    assert_int_equal(m.triangle_count, 2);
    sl_mesh_free(&m);
    /* Same, but the second triangle names position 1 with another vt: 5 vertices. */
    parse_ok("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
             "f 1/1 2/2 3/3\nf 1/4 3/3 4/4\n",
             &m);
    assert_int_equal(m.vertex_count, 5);
    sl_mesh_free(&m);
}

/* Negative indices count back from the last element defined so far. */
static void test_negative_indices(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n"
             "v 5 0 0\nv 6 0 0\nv 5 1 0\nvn 0 0 1\nf -3//-1 -2//-1 -1//-1\n",
             &m);
    assert_int_equal(m.triangle_count, 2);
    assert_vec3_near(m.positions[m.indices[0]], vec3(0, 0, 0), 0.0f);
    assert_vec3_near(m.positions[m.indices[2]], vec3(0, 1, 0), 0.0f);
    assert_vec3_near(m.positions[m.indices[3]], vec3(5, 0, 0), 0.0f); /* -3 after 6 positions = 4 */
    assert_vec3_near(m.positions[m.indices[5]], vec3(5, 1, 0), 0.0f);
    sl_mesh_free(&m);
}

/* Polygons are fans around their first vertex: n corners -> n - 2 triangles (0, i, i+1). */
static void test_fan_triangulation(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", &m);
    assert_int_equal(m.triangle_count, 2);
    static const uint32_t quad[6] = {0, 1, 2, 0, 2, 3};
    for (int k = 0; k < 6; k++)
        assert_int_equal(m.indices[k], quad[k]);
    sl_mesh_free(&m);

    parse_ok("v 1 0 0\nv 0.309 0.951 0\nv -0.809 0.588 0\nv -0.809 -0.588 0\nv 0.309 -0.951 0\n"
             "f 1 2 3 4 5\n",
             &m);
    assert_int_equal(m.triangle_count, 3);
    static const uint32_t pentagon[9] = {0, 1, 2, 0, 2, 3, 0, 3, 4};
    for (int k = 0; k < 9; k++)
        assert_int_equal(m.indices[k], pentagon[k]);
    sl_mesh_free(&m);
}

/* A flat quad without normals gets exactly its face normal at every vertex. */
static void test_flat_quad_normals(void **state)
{
    (void)state;
    sl_mesh m;
    /* In the plane x = 2, counter-clockwise seen from +X: face normal exactly (1, 0, 0). */
    parse_ok("v 2 0 0\nv 2 1 0\nv 2 1 1\nv 2 0 1\nf 1 2 3 4\n", &m);
    for (int v = 0; v < 4; v++)
        assert_vec3_near(m.normals[v], vec3(1, 0, 0), 0.0f);
    sl_mesh_free(&m);
    /* A tilted flat quad: the plane x + y + z = 1 -> normal (1,1,1)/sqrt(3), up to float rounding. */
    parse_ok("v 1 0 0\nv 0 1 0\nv -1 1 1\nv 0 0 1\nf 1 2 3 4\n", &m);
    float s = 1.0f / sqrtf(3.0f);
    for (int v = 0; v < 4; v++)
        assert_vec3_near(m.normals[v], vec3(s, s, s), 1e-6f);
    sl_mesh_free(&m);
}

/* Angle weighting on a configuration where it differs from area weighting and from a plain
 * average. At O = (0,0,0): T1 = (O, (1,0,0), (0,1,0)) has normal +Z and a 90 degree corner at
 * O; T2 = (O, (1,0,1), (1,0,0)) has normal (1,0,1)x(1,0,0) = (0,1,0) and a 45 degree corner
 * at O. Both have area 1/2, so area weighting (and averaging) would give (0,1,1)/sqrt(2);
 * angle weighting gives normalize(pi/2 (0,0,1) + pi/4 (0,1,0)) = (0,1,2)/sqrt(5). */
static void test_angle_weighted_normals(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 0 1\nf 1 2 3\nf 1 4 2\n", &m);
    /* Vertex 0 is O (first corner of the first face). */
    assert_vec3_near(m.positions[0], vec3(0, 0, 0), 0.0f);
    float r5 = 1.0f / sqrtf(5.0f);
    assert_vec3_near(m.normals[0], vec3(0, r5, 2 * r5), 1e-6f);

    /* The public function agrees on the same mesh. */
    for (int v = 0; v < m.vertex_count; v++)
        m.normals[v] = vec3(0, 0, 0);
    sl_mesh_compute_normals(&m);
    assert_vec3_near(m.normals[0], vec3(0, r5, 2 * r5), 1e-6f);
    /* Vertex (1,0,0) has the corner angles the other way round: 45 degrees in T1 (between
     * (-1,1,0) and (-1,0,0)) and 90 in T2 (between (-1,0,0) and (0,0,1)): (0,2,1)/sqrt(5). */
    assert_vec3_near(m.normals[1], vec3(0, 2 * r5, r5), 1e-6f);
    sl_mesh_free(&m);
}

/* Computed normals accumulate per OBJ position, so a UV seam (same v, different vt) does
 * not split the shading: both copies get the same normal. */
static void test_normals_across_uv_seam(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 0 1\nvt 0 0\nvt 1 1\n"
             "f 1/1 2/1 3/1\nf 1/2 4/2 2/2\n",
             &m);
    /* Vertices: (1,1) (2,1) (3,1) (1,2) (4,2) (2,2) -> 6 distinct. */
    assert_int_equal(m.vertex_count, 6);
    float r5 = 1.0f / sqrtf(5.0f);
    assert_vec3_near(m.normals[0], vec3(0, r5, 2 * r5), 1e-6f);
    assert_vec3_near(m.normals[3], vec3(0, r5, 2 * r5), 1e-6f);
    sl_mesh_free(&m);
}

/* A zero normal in the file is replaced by a computed one; degenerate faces never give NaN. */
static void test_degenerate_normals(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n", &m);
    for (int v = 0; v < 3; v++)
        assert_vec3_near(m.normals[v], vec3(0, 0, 1), 0.0f);
    sl_mesh_free(&m);
    /* All three points on a line: no face direction at all -> the +Z fallback, finite. */
    parse_ok("v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n", &m);
    for (int v = 0; v < 3; v++)
        assert_vec3_near(m.normals[v], vec3(0, 0, 1), 0.0f);
    sl_mesh_free(&m);
    /* The same triangle twice with opposite windings: the contributions cancel exactly. */
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n", &m);
    for (int v = 0; v < 3; v++)
        assert_true(isfinite(m.normals[v].x) && isfinite(m.normals[v].y) && isfinite(m.normals[v].z));
    sl_mesh_free(&m);
    /* Huge but finite coordinates: edges overflow float if squared naively. */
    parse_ok("v 0 0 0\nv 3e38 0 0\nv 0 3e38 0\nf 1 2 3\n", &m);
    for (int v = 0; v < 3; v++)
        assert_vec3_near(m.normals[v], vec3(0, 0, 1), 1e-6f);
    sl_mesh_free(&m);
}

/* Statements softlight does not use are accepted; so are CRLF, trailing comments, tabs, vertex
 * colours after v x y z, and a 3-component vt. */
static void test_ignored_statements(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("# header\r\nmtllib x.mtl\r\no thing\r\ng group\r\ns 1\r\nusemtl red\r\n"
             "v 0 0 0 1 0 0\r\nv\t1 0 0 # colour-less\r\nv 0 1 0\r\nvt 0.5 0.5 0\r\n"
             "l 1 2\r\np 1\r\ncurv 0 1 2\r\nvp 0.5\r\nf 1/1 2/1 3/1\r\n",
             &m);
    assert_int_equal(m.triangle_count, 1);
    assert_vec3_near(m.positions[1], vec3(1, 0, 0), 0.0f);
    assert_near(m.texcoords[0].x, 0.5f, 0.0f);
    sl_mesh_free(&m);
}

static void test_index_errors(void **state)
{
    (void)state;
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\n# comment\nf 1 2 4\n", "t.obj:5: face index 4 out of range (1..3)");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "t.obj:4: face index -4 out of range (-3..-1)");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "t.obj:4: face index 0 out of range");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n",
                "t.obj:5: texture coordinate index 2 out of range (1..1)");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n",
                "t.obj:4: normal index 1 out of range (none defined yet)");
    /* Indices must refer backwards: position 4 is defined after the face. */
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\nv 1 1 0\n", "t.obj:4: face index 4 out of range (1..3)");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n", "t.obj:4: face index");
}

static void test_syntax_errors(void **state)
{
    (void)state;
    parse_fails("v 0 0 0\nv 1 0\n", "t.obj:2: expected 3 numbers, got 2");
    parse_fails("v 0 0 zero\n", "t.obj:1: expected a number, got 'zero'");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "t.obj:4: a face needs at least 3 vertices, got 2");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n", "t.obj:4: malformed face vertex");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2 3\n", "t.obj:4: malformed face vertex");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1// 2 3\n", "t.obj:4: malformed face vertex");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf a b c\n", "t.obj:4: face index: expected an integer, got 'a'");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1x 2 3\n", "t.obj:4: face index: expected an integer");
}

static void test_non_finite_rejected(void **state)
{
    (void)state;
    parse_fails("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "t.obj:2: number is not finite");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n", "t.obj:3: number is not finite");
    parse_fails("v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n", "t.obj:2: number is not finite"); /* > FLT_MAX */
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 NaN 1\nf 1//1 2//1 3//1\n", "t.obj:4: number is not finite");
}

static void test_empty_file(void **state)
{
    (void)state;
    parse_fails("", "t.obj: no faces");
    parse_fails("# only a comment\n\n", "t.obj: no faces");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "t.obj: no faces");
    /* A NUL byte means the input is not text. */
    sl_mesh m;
    sl_error err = {0};
    static const char bin[] = "v 0 0 0\nv 1\0 0 0\n";
    assert_false(sl_mesh_parse_obj(bin, sizeof bin - 1, "t.obj", &m, &err));
    assert_non_null(strstr(err.msg, "t.obj:2: NUL byte"));
}

static void test_load_missing_file(void **state)
{
    (void)state;
    sl_mesh m;
    sl_error err = {0};
    assert_false(sl_mesh_load_obj("scenes/meshes/does-not-exist.obj", &m, &err));
    assert_int_equal(err.code, SL_ERR_IO);
    assert_non_null(strstr(err.msg, "does-not-exist.obj"));
}

/* The shipped bunny: counts from the file (1839 v, 3674 f, no vn, no vt), closed and
 * consistently counter-clockwise outward (positive signed volume). */
static void test_bunny(void **state)
{
    (void)state;
    sl_mesh m;
    sl_error err = {0};
    if (!sl_mesh_load_obj("scenes/meshes/bunny.obj", &m, &err)) {
        print_error("%s\n", err.msg);
        fail();
    }
    assert_true(sl_mesh_validate(&m, "bunny.obj", &err));
    assert_int_equal(m.vertex_count, 1839);
    assert_int_equal(m.triangle_count, 3674);
    assert_null(m.texcoords);
    /* Divergence theorem: V = sum over triangles of a . (b x c) / 6. */
    double volume = 0.0;
    vec3 centre = vec3(0, 0, 0);
    for (int v = 0; v < m.vertex_count; v++)
        centre = add3(centre, scale3(m.positions[v], 1.0f / (float)m.vertex_count));
    for (int t = 0; t < m.triangle_count; t++) {
        vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
             c = m.positions[m.indices[3 * t + 2]];
        volume += (double)dot3(a, cross(b, c)) / 6.0;
    }
    assert_true(volume > 150.0); /* the python check of the file gives 194.3 */
    assert_near(volume, 194.288, 0.01);
    /* Computed normals point outward: most agree with (p - centre). */
    int outward = 0;
    for (int v = 0; v < m.vertex_count; v++)
        outward += dot3(m.normals[v], sub3(m.positions[v], centre)) > 0.0f;
    assert_true(outward > m.vertex_count * 9 / 10);
    sl_mesh_free(&m);
}

static void test_validate(void **state)
{
    (void)state;
    sl_mesh m;
    sl_error err = {0};
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", &m);
    m.indices[2] = 3;
    assert_false(sl_mesh_validate(&m, "m", &err));
    assert_non_null(strstr(err.msg, "m: triangle 0: index 3 out of range (0..2)"));
    m.indices[2] = 2;
    m.normals[1] = vec3(0, 0, 2);
    assert_false(sl_mesh_validate(&m, "m", &err));
    assert_non_null(strstr(err.msg, "vertex 1: normal has length 2"));
    m.normals[1] = vec3(0, 0, NAN);
    assert_false(sl_mesh_validate(&m, "m", &err));
    assert_non_null(strstr(err.msg, "vertex 1: normal is not finite"));
    m.normals[1] = vec3(0, 0, 1);
    m.positions[2].y = INFINITY;
    assert_false(sl_mesh_validate(&m, "m", &err));
    assert_non_null(strstr(err.msg, "vertex 2: position is not finite"));
    sl_mesh_free(&m);
    sl_mesh_free(&m); /* freeing twice is harmless: the mesh was zeroed */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_face_form_v),
        cmocka_unit_test(test_face_form_vt),
        cmocka_unit_test(test_face_form_vn),
        cmocka_unit_test(test_face_form_vtn),
        cmocka_unit_test(test_unique_vertices),
        cmocka_unit_test(test_negative_indices),
        cmocka_unit_test(test_fan_triangulation),
        cmocka_unit_test(test_flat_quad_normals),
        cmocka_unit_test(test_angle_weighted_normals),
        cmocka_unit_test(test_normals_across_uv_seam),
        cmocka_unit_test(test_degenerate_normals),
        cmocka_unit_test(test_ignored_statements),
        cmocka_unit_test(test_index_errors),
        cmocka_unit_test(test_syntax_errors),
        cmocka_unit_test(test_non_finite_rejected),
        cmocka_unit_test(test_empty_file),
        cmocka_unit_test(test_load_missing_file),
        cmocka_unit_test(test_bunny),
        cmocka_unit_test(test_validate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
