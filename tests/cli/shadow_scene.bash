# shadow_scene.bash - the hard-case scene of the shadow tests (shadows.sh, gl_shadows.sh): a 4x4
# floor seen from above at an angle, lit by one point light at (0, -0.3, Z), with the objects
# given. Sourced; writes into $T.

# shadow_scene NAME LIGHT_Z OBJECTS...: $T/NAME.json
shadow_scene() {
    local name=$1 z=$2
    shift 2
    local objects=""
    for o in "$@"; do objects="$objects, $o"; done
    cat >"$T/$name.json" <<JSON
{"camera": {"eye": [0, -3.5, 3.5], "target": [0, 0, 0], "up": [0, 0, 1], "fovy": 45},
 "materials": {"m": {"kd": 0.6, "ks": 0.04, "alpha": 10}},
 "objects": [{"shape": "plane", "material": "m", "transform": {"scale": [2, 2, 1]}}$objects],
 "lights": [{"position": [0, -0.3, $z], "intensity": 4}]}
JSON
}
