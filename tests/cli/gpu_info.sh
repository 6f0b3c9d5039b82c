#!/bin/bash
# polyloc gpu info: the headless context reports an OpenGL ES >= 3.1 renderer and compute limits
# (llvmpipe where no GPU is); a platform list with nothing usable fails naming what was tried.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
POLYLOC=$1
out=$("$POLYLOC" gpu info --json)
python3 - "$out" <<'PY'
import json, re, sys
j = json.loads(sys.argv[1])
for k in ("platform", "egl_vendor", "vendor", "renderer", "version"):
    assert j[k], f"gpu info: empty {k}: {j}"
m = re.search(r"OpenGL ES (\d+)\.(\d+)", j["version"])
assert m and (int(m[1]), int(m[2])) >= (3, 1), f"gpu info: not GLES 3.1+: {j['version']}"
assert j["max_ssbo_bindings"] >= 4 and j["max_work_group_invocations"] >= 128, j
assert isinstance(j["software"], bool)
print("gpu info:", j["renderer"], j["version"], "software" if j["software"] else "GPU")
PY
if err=$("$POLYLOC" gpu info --platforms nonsense 2>&1); then
  echo "gpu info with platform 'nonsense' succeeded: $err" >&2; exit 1
fi
grep -q "unknown EGL platform 'nonsense'" <<<"$err" || { echo "unexpected error: $err" >&2; exit 1; }
echo "gpu info: ok"
