# visibility_set.bash - the visibility methods' settings that the benches measure as "the set",
# declared once (sourced by visibility-error.sh, visibility-variants.sh and
# reflection-occlusion.sh; bench_visibility_cost.c, a C program, declares its own copy).
# shellcheck shell=bash disable=SC2034
BEST="--estimator mf --lod pdf --distortion -n 256" # the estimator whose own error is nearly all noise
AO="--ao-radius 1"              # screen-space ambient occlusion within 1 world unit (docs/lighting.md "Ambient occlusion")
SUN="--env-lights 32 --shadows" # the env lights' shadow maps (docs/lighting.md "Shadow maps")
SKY="--sky-maps 32"             # the sky visibility maps (docs/lighting.md "Sky visibility maps")
REFL_LENGTH=7                   # the reflection occlusion's rays' length, world units (docs/lighting.md "Reflection occlusion", why 7)
REFL="--reflection-occlusion $REFL_LENGTH" # the specular's rays traced (docs/lighting.md "Reflection occlusion")
