#!/usr/bin/env bash
# A first session with slosh, run from the repository root after `make run` (or `make
# build-slosh`):   bash examples/session.sh
# It uses the files of examples/ and writes its outputs into a fresh temporary directory. When a
# service answers at $SLOSH_URL (default http://127.0.0.1:8080, what `make run` starts), it also
# asks it over HTTP; otherwise that part is skipped.
set -euo pipefail
SLOSH=${SLOSH:-build/slosh}
URL=${SLOSH_URL:-http://127.0.0.1:8080}
out=$(mktemp -d)
# field PATH...: the members of the JSON on stdin named by dotted paths, on one line.
field() { python3 -c 'import json, sys
d, out = json.load(sys.stdin), []
for path in sys.argv[1:]:
    v = d
    for k in path.split("."): v = v[k]
    out.append(str(round(v, 2) if isinstance(v, float) else v))
print(" ".join(out))' "$@"; }

echo "== the fluid catalogue"
$SLOSH fluids

echo "== a quick look at the thesis format (text summary)"
$SLOSH plan --radius 48.5 --fill 82 --fluid water --stroke 800 --time 1 --strategy multi_notch

echo "== the four acceptance formats, auto (strategy, status, eta motion / rest nonlinear [mm])"
for request in examples/plan-*.json; do
  printf '%-28s ' "$request"
  $SLOSH plan --request "$request" --view compact |
    field strategy status prediction.nonlinear.eta_motion_mm prediction.nonlinear.eta_rest_mm
done

echo "== the uniform law on 800 mm in 0.9 s (eta motion nonlinear / linear [mm])"
$SLOSH simulate --request examples/simulate-800mm-0.9s.json |
  field prediction.nonlinear.eta_motion_mm prediction.linear.eta_motion_mm

echo "== a recipe table: $out/plans.csv"
$SLOSH batch --in examples/recipes.csv --out "$out/plans.csv" --cache "$out/plans.sqlite" \
  --progress never
cut -d, -f1-4 "$out/plans.csv" | head -4

echo "== the cam table of the 1 s plan at a 1 ms cycle: $out/cam.csv"
$SLOSH export --request examples/plan-800mm-1.0s.json --out "$out/cam.csv" --period-ms 1 \
  --cache "$out/plans.sqlite" >/dev/null
head -3 "$out/cam.csv"

if curl -sf "$URL/healthz" >/dev/null 2>&1; then
  echo "== the service at $URL"
  KEY=$(curl -s -X POST "$URL/v1/plans" -H 'Content-Type: application/json' \
    -d @examples/plan-800mm-0.9s.json | field key)
  echo "planned, key $KEY"
  curl -s "$URL/v1/plans/$KEY?view=compact" | field status cached
  curl -s "$URL/v1/plans/$KEY/cam.csv?period_ms=1" -o "$out/cam-http.csv"
  head -2 "$out/cam-http.csv"
else
  echo "== no service at $URL (start one with make run): the HTTP part is skipped"
fi
echo "outputs in $out"
