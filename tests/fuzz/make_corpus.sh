#!/usr/bin/env bash
# Regenerate the seed corpus from the demonstration scenes:
#   corpus/scene_json/  every scenes/*.json
#   corpus/scene_text/  every scenes/<name>/ as config.txt, "%%", materials.txt,
#                       "%%", objects.txt in one file (see fuzz_scene_text.c)
#   corpus/api/         a few fixed byte programs (see fuzz_api.c)
# Usage: tests/fuzz/make_corpus.sh   (from anywhere)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
mkdir -p "$here/corpus/scene_json" "$here/corpus/scene_text" "$here/corpus/api"
rm -f "$here"/corpus/scene_json/* "$here"/corpus/scene_text/*
for f in "$top"/scenes/*.json "$top"/tests/scene/bad/*.json; do
  cp "$f" "$here/corpus/scene_json/"
done
for d in "$top"/scenes/*/ "$top"/tests/scene/bad/*/; do
  [ -f "$d/config.txt" ] || continue
  n=$(basename "$d")
  { cat "$d/config.txt"; printf '%%%%\n'; cat "$d/materials.txt" 2>/dev/null || true; printf '%%%%\n'
    cat "$d/objects.txt" 2>/dev/null || true; } > "$here/corpus/scene_text/$n.txt"
done
# API programs: deterministic bytes (a header, then ops; see fuzz_api.c).
python3 - "$here/corpus/api" <<'PY'
import os, random, sys
out = sys.argv[1]
hdr = bytes([8, 3, 4, 0, 0, 0, 0, 0, 2, 0, 0, 30, 0, 1])  # 8 bodies, dt 1e-3, gravity small
progs = {
    # material, pair, plane, two spheres, steps, checkpoint, queries
    "basic": hdr + bytes([0, 2, 0, 1, 1, 0, 0, 2, 2, 2, 4, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0,
                          0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 7, 2, 10,
                          1, 0, 5, 3, 11, 0, 0, 8, 2]),
    # huge and non-finite values through setters, then steps
    "bad_values": hdr + bytes([2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 6, 0, 1, 200, 19, 230, 240,
                               7, 2, 6, 0, 3, 200, 19, 19, 19, 7, 2, 6, 0, 0, 200, 20, 21, 250, 7, 2]),
    "remove_stale": hdr + bytes([2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 5, 0, 5, 0, 6, 0, 1, 0, 0,
                                 0, 0, 11, 0, 0, 10, 0, 0, 0, 7, 1]),
}
rng = random.Random(8)
for i in range(5):
    progs["random%d" % i] = bytes(rng.randrange(256) for _ in range(300))
for name, data in progs.items():
    with open(os.path.join(out, name), "wb") as f:
        f.write(data)
PY
echo "corpus: $(ls "$here/corpus/scene_json" | wc -l) json, $(ls "$here/corpus/scene_text" | wc -l) text, $(ls "$here/corpus/api" | wc -l) api"
