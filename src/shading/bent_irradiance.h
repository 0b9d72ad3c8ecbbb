/* bent_irradiance.h - the direction along which the diffuse term reads the irradiance map when
 * the ambient occlusion pass left a visibility cone (src/occlusion/gtao.h: bent normal B, AO).
 * One function for the C port, the batched path and the tests; shaders/lighting.frag has its
 * GLSL twin (bent_irradiance_dir), the same operations in the same order.
 *
 * The diffuse term is AO E(D) with D = normalize(N + (1 - AO)(B - N)): the irradiance along a
 * normal bent towards the visible directions by the share the occluders hide. The AO alone says
 * how much of the cosine lobe is hidden, not where; the bent normal says where, and E(D) then
 * weighs the sky on the open side more than the sky behind the occluders (a floor beside a wall
 * under a sky brighter on the wall's side reads darker than AO E(N)). The weight (1 - AO) keeps
 * D = N on open ground, where B is the pass's own noise (its AO there is up to 0.025 short of 1),
 * and reaches B when nearly everything is hidden. docs/lighting.md "Ambient occlusion" gives
 * the forms measured against the visibility truth and why this one. */
#ifndef SL_BENT_IRRADIANCE_H
#define SL_BENT_IRRADIANCE_H

#include <softlight/glsl.h>

/* GLSL: bent_irradiance_dir. N and B unit vectors on the same side (B is a mean of directions in
 * N's hemisphere), ao in [0, 1]. */
static inline vec3 sl_bent_irradiance_dir(vec3 N, vec3 B, float ao)
{
    return normalize(add(N, scale(sub(B, N), 1.0f - ao)));
}

#endif
