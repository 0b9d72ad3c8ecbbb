# glare_scene.bash - the scene of the sun's glow tests (sun_shadows.sh against the visibility
# truth, gl_sun_shadows.sh against softlight-gl): a glossy floor (GGX r 0.3) facing a sun of two
# texels 25 degrees up in a glare of ten texels of 300 (sun_sky.py), a box between the two.
# shellcheck shell=bash

# glare_scene DIR: writes DIR/glare.pfm and DIR/glare.json
glare_scene() {
    python3 "$(dirname "${BASH_SOURCE[0]}")/sun_sky.py" "$1/glare.pfm" 25 90 0 300
    cat >"$1/glare.json" <<JSON
{"camera": {"eye": [0, -3.5, 1.5], "target": [0, 0, 0], "up": [0, 0, 1], "fovy": 45},
 "environment": {"hdr": "$1/glare.pfm"},
 "materials": {"floor": {"brdf": "ggx", "kd": 0.05, "ks": 0.9, "roughness": 0.3},
               "m": {"kd": 0.6, "ks": 0.04, "alpha": 10}},
 "objects": [{"shape": "plane", "material": "floor", "transform": {"scale": [3, 3, 1]}},
   {"shape": "box", "material": "m", "transform": {"translate": [0, 1.2, 0.4], "scale": 0.4}}]}
JSON
}
