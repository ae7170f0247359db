#!/usr/bin/env bash
# The reproducers of issue 20's first list, run against the program as a user would: each must
# give a clean error (exit 1 or 2, one line starting "inhap: error:", naming the file) or a correct
# result. Prints one line per case and a summary; exit 1 when a case fails.
# Usage: reproducers.sh INHAP_BINARY SOURCE_DIR        (ctest: hardening.reproducers)
set -uo pipefail
inhap=$1 src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
corpus=$src/tests/fuzz/corpus
failed=0 passed=0

say() { printf '%-4s %s\n' "$1" "$2"; }
fail() { say FAIL "$1: $2"; failed=$((failed + 1)); }
pass() { say ok "$1"; passed=$((passed + 1)); }

# clean_error NAME EXIT NEEDLE... -- COMMAND...: COMMAND exits EXIT with one line of output that
# starts with "inhap: error:" and contains every NEEDLE.
clean_error() {
  local name=$1 want=$2
  shift 2
  local needles=()
  while [ "$1" != "--" ]; do needles+=("$1"); shift; done
  shift
  local out rc
  out=$("$@" 2>&1)
  rc=$?
  local lines
  lines=$(printf '%s\n' "$out" | grep -c .)
  if [ "$rc" -ne "$want" ]; then fail "$name" "exit $rc (expected $want): ${out:0:300}"; return; fi
  if [ "$lines" -ne 1 ]; then fail "$name" "$lines lines of output: ${out:0:300}"; return; fi
  case "$out" in "inhap: error:"*) ;; *) fail "$name" "no inhap: error: prefix: ${out:0:300}"; return ;; esac
  for n in "${needles[@]}"; do
    case "$out" in *"$n"*) ;; *) fail "$name" "'$n' not in: ${out:0:300}"; return ;; esac
  done
  pass "$name (exit $rc: ${out:0:150})"
}

# A small recording: the probe pushes straight down into a plane (k = 1 N/mm), proxy on the plane.
awk 'BEGIN { print "t,px,py,pz,fx,fy,fz,qx,qy,qz,contact";
  for (i = 0; i < 6000; i++) { t = i / 1000; x = 10 * sin(t); d = 1.5 + sin(3 * t);
    printf "%.3f,%.4f,0,%.4f,0,0,%.4f,%.4f,0,0,1\n", t, x, -d, d, x } }' >push.csv

# --- A file or flag can lift the force limit -------------------------------------------------
sed 's/"force_limit_n": 6.2/"force_limit_n": 1e9/' "$corpus/model/small.json" >lift.json
clean_error "model file force_limit_n 1e9" 1 lift.json force_limit_n -- \
  "$inhap" model render --model lift.json --recording push.csv --out f.csv
clean_error "model train --force-limit 1000" 2 "--force-limit" -- \
  "$inhap" model train --recording push.csv --preset world --force-limit 1000 --out m.json

# --- Readers that trust declared sizes ---------------------------------------------------------
{ printf 'P5\n20000 20000\n255\n'; head -c 300 /dev/zero; } >big.pgm
clean_error "PGM declaring 20000x20000 in $(stat -c %s big.pgm) bytes" 1 big.pgm -- \
  "$inhap" mesh heightmap big.pgm --spacing 1 --out big.ply
{ printf 'P5\n65536 65536\n255\n'; head -c 300 /dev/zero; } >huge.pgm
clean_error "PGM declaring 65536x65536" 1 huge.pgm -- \
  "$inhap" mesh heightmap huge.pgm --spacing 1 --out huge.ply
if command -v /usr/bin/time >/dev/null; then
  kb=$(/usr/bin/time -f %M "$inhap" mesh heightmap big.pgm --spacing 1 --out big.ply 2>&1 >/dev/null | tail -1)
  if [ "${kb:-999999}" -lt 200000 ]; then pass "PGM 20000x20000: peak memory ${kb} kB"; else fail "PGM memory" "peak ${kb} kB"; fi
fi

# --- Outputs inhap cannot read back, with exit 0 -----------------------------------------------
awk -F, 'NR == 4 { $13 = "1e308" } { print }' OFS=, "$corpus/cycles/small.csv" >bigcycle.csv
clean_error "sys fit on a 1e308 coordinate" 1 "bigcycle.csv:4" -- \
  "$inhap" sys fit bigcycle.csv --out big-sys.json
[ -e big-sys.json ] && fail "sys fit 1e308" "big-sys.json written"
sed 's/"base_center": \[0.0, 0.0, 0.0\]/"base_center": [1e308, 0.0, 0.0]/' "$corpus/scene/dome.json" >farscene.json
clean_error "scene with a 1e308 centre" 1 farscene.json -- \
  "$inhap" lab record --scene-file farscene.json --operator tap --seconds 1 --out far.csv
[ -e far.csv ] && fail "lab record 1e308" "far.csv written"
sed 's/spacings: 1 2 3/spacings: nan 2 2/' "$corpus/nrrd/attached.nrrd" >nan.nrrd
clean_error "NRRD spacings: nan 2 2" 1 nan.nrrd spacings -- \
  "$inhap" mesh from-volume nan.nrrd --out vol.ply
sed 's/spacings: 1 2 3/spacings: 1e308 1e308 1e308/' "$corpus/nrrd/attached.nrrd" >huge.nrrd
clean_error "NRRD spacings: 1e308" 1 huge.nrrd spacings -- \
  "$inhap" mesh from-volume huge.nrrd --out vol.ply
clean_error "from-volume with no isosurface names the file" 1 attached.nrrd -- \
  "$inhap" mesh from-volume "$corpus/nrrd/attached.nrrd" --iso 100000 --out vol.ply
printf 'v -1e308 0 0\nv 1e308 0 0\nv 0 1 0\nf 1 2 3\n' >huge.obj
clean_error "mesh info on vertices at +-1e308" 1 huge.obj "finite size" -- "$inhap" mesh info huge.obj
clean_error "mesh convert on vertices at +-1e308" 1 huge.obj "finite size" -- \
  "$inhap" mesh convert huge.obj huge.ply
printf '0,0,0\n0,1e308,0\n0,-1e308,0\n' >huge-h.csv
clean_error "mesh heightmap on heights of +-1e308" 1 huge-h.csv "finite size" -- \
  "$inhap" mesh heightmap huge-h.csv --spacing 1 --out huge-h.ply
sed 's/"f_limit": 0.5/"f_limit": 1e308/' "$corpus/sys/small.json" >huge-sys.json
clean_error "sys table on f_limit 1e308" 1 huge-sys.json f_limit -- \
  "$inhap" sys table huge-sys.json

# --- Multi-file outputs are all-or-nothing -----------------------------------------------------
echo old >r.csv
mkdir r.truth.csv
clean_error "lab record with its truth path blocked" 1 r.truth.csv -- \
  "$inhap" lab record --scene dome --operator tap --seconds 1 --out r.csv
[ "$(cat r.csv)" = old ] || fail "lab record blocked truth" "r.csv was replaced"
"$inhap" lab record --scene dome --operator tap --seconds 4 --probe tip --out taps.csv >/dev/null 2>&1
echo old >p.ply
clean_error "shape contacts --csv into a missing folder" 1 missing -- \
  "$inhap" shape contacts taps.csv --out p.ply --csv missing/t.csv
[ "$(cat p.ply)" = old ] || fail "shape contacts" "p.ply was replaced"
mkdir s.cycles.csv
start=$(date +%s)
clean_error "sys palpate with a blocked output path" 1 s.cycles.csv -- \
  "$inhap" sys palpate --scene planar --out s.json
[ $(($(date +%s) - start)) -le 10 ] || fail "sys palpate" "took $(($(date +%s) - start)) s before failing"

# --- Unclean errors ----------------------------------------------------------------------------
sed 's/"force_limit_n": 6.2/"force_limit_n": 1e999/' "$corpus/model/small.json" >overflow.json
clean_error "JSON number 1e999" 1 overflow.json -- \
  "$inhap" model render --model overflow.json --recording push.csv --out f.csv
{ printf '{"format": "'; head -c 20000000 /dev/zero | tr '\0' x; printf '"}'; } >long.json
out=$("$inhap" model render --model long.json --recording push.csv --out f.csv 2>&1)
if [ $? -eq 1 ] && [ ${#out} -lt 1000 ]; then pass "20 MB string quoted in ${#out} characters"
else fail "20 MB string" "exit/size: ${#out} characters"; fi
mkdir adir.ply
clean_error "a directory passed as a mesh" 1 adir.ply directory -- "$inhap" mesh info adir.ply
sed '0,/"id": [0-9]*/s//"id": 4e9/' "$corpus/sys/small.json" >bigid.json
clean_error "sys.json id 4e9" 1 bigid.json -- "$inhap" sys table bigid.json
clean_error "unknown flag" 2 "--bogus" -- "$inhap" mesh info --bogus x.ply
clean_error "mistyped subcommand" 2 "did you mean 'inhap mesh info'" -- "$inhap" mesh inf x.ply

# --- Servo faults ------------------------------------------------------------------------------
printf '0 0 0 0 0\n0 0 0 0 0\n0 0 0 0 0\n0 0 0 0 0\n0 0 0 0 0\n' >flat.csv
"$inhap" mesh heightmap flat.csv --spacing 10 --out flat.ply >/dev/null 2>&1
stroke_check() {  # NAME STIFFNESS FORCE: finishes (exit 0), holds FORCE within 5 % mid-stroke,
  # never at the device's 6.2 N clamp in contact
  local name=$1 k=$2 f=$3
  local out
  out=$("$inhap" tca stroke --mesh flat.ply --stiffness "$k" --force "$f" --from 10,20 --to 30,20 \
    --out stroke.csv 2>&1)
  if [ $? -ne 0 ]; then fail "$name" "${out:0:300}"; return; fi
  local stats  # contact ticks with the probe between x = 12 and 28 mm: mean, min, max of f_z;
  # contact ticks at the clamp (|f| >= 6.19 N)
  stats=$(awk -F, '/^[0-9]/ && $NF == 1 && sqrt($11^2 + $12^2 + $13^2) >= 6.19 { c++ }
      /^[0-9]/ && $NF == 1 && $2 > 12 && $2 < 28 { s += $13; n++;
      if (n == 1 || $13 < lo) lo = $13; if (n == 1 || $13 > hi) hi = $13 }
    END { if (n) printf "%.3f %.3f %.3f %d %d", s / n, lo, hi, n, c; else print "nan nan nan 0 0" }' stroke.csv)
  read -r mean lo hi n clamped <<<"$stats"
  if awk -v a="$lo" -v b="$hi" -v f="$f" -v n="$n" -v c="$clamped" 'BEGIN { exit !(n > 500 && a > 0.95 * f && b < 1.05 * f && c == 0) }'; then
    pass "$name: f_z mid-stroke mean $mean N, range $lo..$hi N over $n ticks, $clamped at the clamp"
  else fail "$name" "f_z mid-stroke mean $mean N, range $lo..$hi N over $n ticks for $f N, $clamped contact ticks at the 6.2 N clamp"; fi
}
stroke_check "tca stroke 4.5 N on 0.2 N/mm" 0.2 4.5
stroke_check "tca stroke 1.5 N on 0.1 N/mm" 0.1 1.5
stroke_check "tca stroke 2 N on 100 N/mm (the stiffest allowed)" 100 2
# 1e5 N/mm sat at the 6.2 N clamp for its first 182 ms of contact: refused, as flag or map.
clean_error "tca stroke --stiffness 1e5" 1 "--stiffness" "100] N/mm" -- \
  "$inhap" tca stroke --mesh flat.ply --stiffness 1e5 --force 2 --from 10,20 --to 30,20 --out stroke.csv
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float stiffness\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0.5\n40 0 0 1e5\n40 40 0 0.5\n0 40 0 0.5\n3 0 1 2\n3 0 2 3\n' >stiff.ply
clean_error "tca stroke on a mesh of 1e5 N/mm" 1 stiff.ply "vertex 1" "100 N/mm" -- \
  "$inhap" tca stroke --mesh stiff.ply --force 2 --from 10,20 --to 30,20 --out stroke.csv

# --- Usability ---------------------------------------------------------------------------------
for c in "lab record:--seconds FLOAT:FLOAT in [0.001 - 3600]=60" "shape contacts:--eps FLOAT:POSITIVE=0.2" \
         "model train:--tail,--no-tail{false}"; do
  cmd=${c%%:*} want=${c#*:}
  # shellcheck disable=SC2086
  if "$inhap" $cmd --help 2>&1 | grep -qF -- "$want"; then
    if [ "$cmd" = "model train" ]; then fail "help of $cmd" "still shows '$want'"; else pass "help of $cmd shows '$want'"; fi
  else
    if [ "$cmd" = "model train" ]; then pass "help of $cmd no longer shows '$want'"; else fail "help of $cmd" "no '$want'"; fi
  fi
done
clean_error "lab record --seconds 86400" 2 "--seconds" -- \
  "$inhap" lab record --scene dome --seconds 86400 --out long.csv
out=$("$inhap" model train --recording push.csv --preset world --centers 20 --bins 2 --out short.json 2>&1)
case "$out" in *"warning: only 6.0 s of contact"*) pass "5-6 s of training data is warned about" ;;
  *) fail "short training data" "${out:0:300}" ;; esac
# Every time the demo's help gives for --quick (the description and the flag) is the same.
times=$("$inhap" demo --help 2>&1 | tr '\n' ' ' | grep -oE -- '--quick[^.;]*' | grep -oE '[0-9]+ ?(s|min)\b' | sort -u)
if [ "$(printf '%s\n' "$times" | grep -c .)" -eq 1 ]; then pass "demo help gives one time for --quick: $times"
else fail "demo help" "times for --quick: $(printf '%s ' "$times")"; fi

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
