/* quad.c - the 2x2 quad of a derivative-taking fragment shader: the derivative and
 * discard built-ins (softlight/program.h) and the rounds the tile stage runs a quad in (tile.c).
 *
 * A C shader is an ordinary function run once per fragment: it cannot stop at a dFdx
 * and wait for its three neighbours as GPU lanes in lock-step do. So the tile stage runs
 * the quad's four lanes through the whole shader in rounds. In a round, the k-th
 * derivative call of a lane records its argument and returns the difference of the
 * values the round before recorded for call k (0 in the first round, or where a lane
 * did not reach call k). When a round records exactly what the round before recorded,
 * every derivative it returned is the difference of values the shader really computed
 * with those derivatives: by induction on call order (call 0's argument depends on no
 * derivative; if calls 0..k-1 got the lock-step values, so does call k) it is the
 * lock-step result. Round r has the first r calls right, so a quad of K calls needs at
 * most K + 1 rounds; a shader whose calls read varyings only needs 2, one without any
 * call in the quad 1.
 *
 * A store outside the texel (the image store of GLSL; the G-buffer's extra plane) cannot be
 * taken back as a round's scratch texels are, and a lane may store in a round and discard
 * in the next (a texture's alpha at a level the zero derivatives of round 1 picked). So a
 * program that declares `stores` runs its rounds with stores off (sl_fragment_stores) and,
 * at the fixed point, one more round that repeats the last one's bits with stores on. */
#include "rast_internal.h"
#include "raster.h"

#include <string.h>

void sl_quad_derivative(const sl_fragment_in *in, sl_derivative kind, const float *v, int n, float *d)
{
    bool coarse = kind == SL_DFDX_COARSE || kind == SL_DFDY_COARSE || kind == SL_FWIDTH_COARSE;
    float dx[4], dy[4];
    sl_quad_gradients(in, coarse, v, n, dx, dy);
    for (int i = 0; i < n; i++) {
        switch (kind) {
        case SL_DFDX_FINE:
        case SL_DFDX_COARSE:
            d[i] = dx[i];
            break;
        case SL_DFDY_FINE:
        case SL_DFDY_COARSE:
            d[i] = dy[i];
            break;
        case SL_FWIDTH_FINE:
        case SL_FWIDTH_COARSE:
            d[i] = fabsf(dx[i]) + fabsf(dy[i]);
            break;
        }
    }
}

/* Record v as this lane's next call; dx, dy from the round before's records of that call
 * (0 where a lane of the pair has none): right minus left, upper minus lower. */
void sl_quad_gradients(const sl_fragment_in *in, bool coarse, const float *v, int n, float *dx, float *dy)
{
    for (int i = 0; i < n; i++)
        dx[i] = dy[i] = 0.0f;
    sl_quad *q = in->quad;
    if (!q || !q->derivs)
        return;
    int lane = in->lane, k = q->count[q->cur][lane];
    if (k >= RAST_QUAD_CALLS)
        return;
    float *rec = q->rec[q->cur][lane][k];
    for (int i = 0; i < 4; i++)
        rec[i] = i < n ? v[i] : 0.0f;
    q->count[q->cur][lane] = k + 1;
    int ax = coarse ? 0 : lane & 2, bx = coarse ? 1 : lane | 1;
    int ay = coarse ? 0 : lane & 1, by = coarse ? 2 : lane | 2;
    const int prev = q->cur ^ 1;
    const int *have = q->count[prev];
    if (have[ax] > k && have[bx] > k)
        for (int i = 0; i < n; i++)
            dx[i] = q->rec[prev][bx][k][i] - q->rec[prev][ax][k][i];
    if (have[ay] > k && have[by] > k)
        for (int i = 0; i < n; i++)
            dy[i] = q->rec[prev][by][k][i] - q->rec[prev][ay][k][i];
}

void sl_discard(const sl_fragment_in *in)
{
    if (in->quad)
        in->quad->discarded[in->lane] = true;
}

bool sl_fragment_stores(const sl_fragment_in *in)
{
    return !in->helper && !(in->quad && in->quad->rehearsal);
}

void sl_rast_quad_begin(sl_quad *q, bool rounds, bool stores)
{
    q->cur = 0;
    q->derivs = rounds;
    q->rehearsal = rounds && stores;
    memset(q->count, 0, sizeof q->count);
    memset(q->discarded, 0, sizeof q->discarded);
}

void sl_rast_quad_round(sl_quad *q)
{
    q->cur ^= 1;
    memset(q->count[q->cur], 0, sizeof q->count[q->cur]);
    memset(q->discarded, 0, sizeof q->discarded);
}

static bool fixed(const sl_quad *q)
{
    const int cur = q->cur, prev = cur ^ 1;
    for (int l = 0; l < 4; l++) {
        int n = q->count[cur][l];
        if (n != q->count[prev][l])
            return false;
        if (n > RAST_QUAD_CALLS)
            n = RAST_QUAD_CALLS;
        /* bitwise: -0 against +0 or a NaN's payload is one more round, never a wrong stop */
        if (memcmp(q->rec[cur][l], q->rec[prev][l], (size_t)n * sizeof q->rec[cur][l][0]) != 0)
            return false;
    }
    return true;
}

bool sl_rast_quad_done(sl_quad *q, int rounds)
{
    /* a fixed point comes by round calls + 1; the bound only guards that proof */
    if (!fixed(q) && rounds <= RAST_QUAD_CALLS)
        return false;
    if (!q->rehearsal)
        return true;
    q->rehearsal = false; /* the fixed point's bits once more, stores on */
    return false;
}
