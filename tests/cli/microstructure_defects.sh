#!/usr/bin/env bash
# Defect studies of Le 2014 chapter 3 on a synthetic microstructure (docs/microstructures.md):
# a longitudinal Bi2212 filament in silver drawn by scripts/microstructure, read as an image,
# under a 0.1% macroscopic strain through fictitious silver layers (tests/cli/decks/filament.yaml),
# the largest von Mises stress of each phase from `peri sweep` (max_von_mises:MATERIAL, the
# layers left out). Seed 000's qualitative findings (sections 3.4.4 to 3.4.10):
# - a void raises the Bi2212 maximum far more than a soft or hard inclusion of the same shape
#   (4 x 8 um at the filament's centre): its rise over the defect-free filament is more than
#   five times theirs (soft: half, hard: twice the Bi2212 bulk modulus);
# - a rectangle void 4 um wide: the Bi2212 maximum grows with its height across the load
#   (2, 6, 10, 14 um inside the 24 um filament);
# - equal-area voids (64 um^2) rank by aspect ratio: h:w = 4 above 1 above 0.25;
# - cooling by 300 K (tests/cli/decks/filament_cooling.yaml, a free body): Bi2212 in
#   compression and silver in tension (mean stress tr(sigma)/3 of each phase), and the
#   volume-weighted sum of the two mean stresses vanishes within 5% of either term, as the
#   mean stress of a body without external load must (integral of sigma dV = 0);
# - history.csv has the per-phase columns (max_von_mises_MAT, max_von_mises_at_MAT_x, _y,
#   mean_stress_MAT) with their units, and the summary prints the per-phase maxima.
# Usage: bash tests/cli/microstructure_defects.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
if ! python3 -c 'import zlib' 2>/dev/null; then
  echo "SKIP: $CLI_NAME: no python3 for scripts/microstructure"
  exit 0
fi
cp "$DECKS/filament.yaml" "$DECKS/filament_cooling.yaml" "$TMP/"
python3 scripts/microstructure longitudinal "$TMP/filament.png" --width 120 --height 60 --filament-width 0.4 \
  --waviness 0.02 --seed 1 || fail "scripts/microstructure longitudinal"
deck="$TMP/filament.yaml"

# column K (from 1) of the data rows of the last sweep table, one value per line
values() { grep -E '^\| [^-]' "$RUN_STDOUT" | tail -n +2 | awk -F'|' -v k="$1" '{ gsub(/ /, "", $(k + 1)); print $(k + 1) }'; }

run_peri sweep "$deck" --set-list discretization.fill.2.material=bi2212,void,soft,hard --quantity max_von_mises:bi2212
expect_status 0
read -r none void soft hard <<<"$(values 2 | tr '\n' ' ')"
awk -v n="$none" -v v="$void" -v s="$soft" -v h="$hard" 'BEGIN {
  ds = s - n; if (ds < 0) ds = -ds; dh = h - n; if (dh < 0) dh = -dh
  exit !(v - n > 5 * (ds > dh ? ds : dh)) }' ||
  fail "Bi2212 maximum: none $none, void $void, soft $soft, hard $hard Pa: the void's rise is not 5 times the inclusions'"
pass "Bi2212 maximum von Mises: no defect $none, void $void, soft $soft, hard $hard Pa"

run_peri sweep "$deck" --set-list "discretization.fill.2.min=[58e-6,29e-6],[58e-6,27e-6],[58e-6,25e-6],[58e-6,23e-6]" \
  --set-list "discretization.fill.2.max=[62e-6,31e-6],[62e-6,33e-6],[62e-6,35e-6],[62e-6,37e-6]" --quantity max_von_mises:bi2212
expect_status 0
heights=$(values 3 | tr '\n' ' ')
echo "$heights" | awk '{ for (k = 2; k <= NF; ++k) if (!($k > $(k - 1))) exit 1 }' ||
  fail "Bi2212 maximum does not grow with the void's height 2, 6, 10, 14 um: $heights"
pass "rectangle void 4 um wide, heights 2, 6, 10, 14 um: Bi2212 maximum $heights Pa"

run_peri sweep "$deck" --set-list "discretization.fill.2.min=[58e-6,22e-6],[56e-6,26e-6],[52e-6,28e-6]" \
  --set-list "discretization.fill.2.max=[62e-6,38e-6],[64e-6,34e-6],[68e-6,32e-6]" --quantity max_von_mises:bi2212
expect_status 0
ratios=$(values 3 | tr '\n' ' ')
echo "$ratios" | awk '{ exit !($1 > $2 && $2 > $3) }' || fail "equal-area voids h:w = 4, 1, 0.25 do not rank: $ratios"
pass "equal-area voids h:w = 4, 1, 0.25: Bi2212 maximum $ratios Pa"

run_peri run "$TMP/filament_cooling.yaml" --output "$TMP/cool"
expect_status 0
expect_stdout_matches "^  max von Mises bi2212: [0-9.e+]+ Pa at \(.*\), mean stress -"
h="$TMP/cool/history.csv"
for c in max_von_mises_bi2212 max_von_mises_at_bi2212_x max_von_mises_at_bi2212_y mean_stress_bi2212 mean_stress_silver; do
  [[ -n "$(csv_column "$h" "$c")" ]] || fail "history.csv has no column $c"
done
head -1 "$h" | tr ',' '\n' > "$TMP/names"
tail -1 "$TMP/cool/history_units.csv" | tr ',' '\n' > "$TMP/units"
paste -d' ' "$TMP/names" "$TMP/units" | grep -qx "max_von_mises_at_silver_x m" || fail "unit of max_von_mises_at_silver_x is not m"
paste -d' ' "$TMP/names" "$TMP/units" | grep -qx "mean_stress_silver Pa" || fail "unit of mean_stress_silver is not Pa"
bi=$(tail -1 "$h" | cut -d, -f"$(csv_column "$h" mean_stress_bi2212)")
ag=$(tail -1 "$h" | cut -d, -f"$(csv_column "$h" mean_stress_silver)")
# the phases' volume fractions: one node per pixel (spacing = pixel size), black = Bi2212
fbi=$(python3 - "$TMP/filament.png" <<'PYEOF'
import struct, sys, zlib
data = open(sys.argv[1], "rb").read()
pos, idat, w, h = 8, b"", 0, 0
while pos < len(data):
    n, kind = struct.unpack(">I4s", data[pos:pos + 8])
    if kind == b"IHDR":
        w, h = struct.unpack(">II", data[pos + 8:pos + 16])
    if kind == b"IDAT":
        idat += data[pos + 8:pos + 8 + n]
    pos += 12 + n
raw = zlib.decompress(idat)  # scripts/microstructure writes filter 0, 8-bit RGB
black = sum(raw[r * (3 * w + 1) + 1 + 3 * c] == 0 for r in range(h) for c in range(w))
print(black / (w * h))
PYEOF
)
awk -v b="$bi" -v a="$ag" -v f="$fbi" 'BEGIN {
  tb = f * b; ta = (1 - f) * a; s = tb + ta; if (s < 0) s = -s; if (tb < 0) tb = -tb
  exit !(b < 0 && a > 0 && s < 0.05 * tb) }' ||
  fail "cooling by 300 K: mean stress Bi2212 $bi Pa, silver $ag Pa (Bi2212 fraction $fbi): not compression / tension in balance"
pass "cooling by 300 K: Bi2212 mean stress $bi Pa (compression), silver $ag Pa (tension), Bi2212 fraction $fbi"
