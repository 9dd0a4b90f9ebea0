#!/usr/bin/env bash
# Issue 14's speed goals as ratios, measured side by side in one session: the build before
# the issue (commit 4cfb922, or the commit named by KANESTOP_BASELINE) against this checkout.
#
#   benches/then_and_now.sh [ROUNDS]          # default 3 rounds
#   KANESTOP_CALLGRIND=1 benches/then_and_now.sh   # also instruction counts (valgrind)
#
# The shared machine's absolute speed moves by a third from hour to hour, so a figure measured
# today against one quoted from yesterday says little; two builds alternated in one session do.
# The baseline is checked out in a temporary git worktree, benches/replay.rs (which uses only
# interfaces the baseline already had) is copied into it, and both are built in release mode.
# Each round runs both builds, the order alternating from
# round to round: the replayed right-hand side (case 1, every solve of its run through
# Dynamics) and weight alone at N = 46 (benches/replay.rs), case 1's whole `kanestop run`, and
# the 19 paper cases' `kanestop batch` (CPU time of the process and its threads). Prints every
# measurement and, per round, then / now. Any failed step ends the script with its error.
# (Weight alone's goal is stated against a hand-written C planar ABA, not the old build:
# `cargo bench --bench kernels -- c_aba` measures that one; the old build's figure is here
# for the record.)
set -euo pipefail

rounds=${1:-3}
case $rounds in
'' | *[!0-9]* | 0)
    echo "then_and_now.sh: ROUNDS must be a whole number of at least 1, not '$rounds'" >&2
    exit 2
    ;;
esac
base=${KANESTOP_BASELINE:-4cfb922}
here=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'git -C "$here" worktree remove --force "$work/then" >/dev/null 2>&1 || true; rm -rf "$work"' EXIT

git -C "$here" worktree add --quiet --detach "$work/then" "$base"
cp "$here/benches/replay.rs" "$work/then/benches/replay.rs"
grep -q 'name = "replay"' "$work/then/Cargo.toml" ||
    printf '\n[[bench]]\nname = "replay"\nharness = false\n' >>"$work/then/Cargo.toml"

declare -A dir bench kanestop
dir[then]=$work/then
dir[now]=$here

build() { # WHICH: builds kanestop and the replay bench of that tree, notes their executables
    local which=$1 json
    json=$(cd "${dir[$which]}" && cargo build --release --quiet --bin kanestop --message-format=json-render-diagnostics)
    kanestop[$which]=$(printf '%s\n' "$json" |
        sed -n '/"kind":\["bin"\][^}]*"name":"kanestop"/s/.*"executable":"\([^"]*\)".*/\1/p' | tail -1)
    json=$(cd "${dir[$which]}" && cargo bench --bench replay --no-run --quiet --message-format=json-render-diagnostics)
    bench[$which]=$(printf '%s\n' "$json" |
        sed -n '/"name":"replay"/s/.*"executable":"\([^"]*\)".*/\1/p' | tail -1)
    for exe in "${kanestop[$which]}" "${bench[$which]}"; do
        [ -n "$exe" ] && [ -x "$exe" ] || {
            echo "then_and_now.sh: the $which build left no executable '$exe'" >&2
            exit 1
        }
    done
}
echo "building $base (then) and this checkout (now)…" >&2
build then
build now

cpu_of() { # command… -> user + system CPU seconds of the command and its threads
    # kanestop's exit codes 0 (done) and 4 (a design check failed: a result like any other)
    # are measurements; 1, 2 and 3 (a scene failed or was refused) are not. The children's
    # times are taken as a difference: Linux keeps them across exec, so a launcher that ran
    # processes before exec'ing Python (a pyenv shim does, about 0.05 s) would add its own.
    python3 -c '
import resource, subprocess, sys
before = resource.getrusage(resource.RUSAGE_CHILDREN)
p = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
if p.returncode not in (0, 4):
    sys.exit(f"{sys.argv[1:]} exited with {p.returncode}:\n{p.stderr}")
r = resource.getrusage(resource.RUSAGE_CHILDREN)
print(f"{r.ru_utime + r.ru_stime - before.ru_utime - before.ru_stime:.3f}")' "$@"
}

replay() { # WHICH -> "rhs_cpu_us gravity_cpu_us"
    local out
    out=$(cd "${dir[$1]}" && "${bench[$1]}" 1)
    printf '%s\n' "$out" | awk '
        $1 == "1" && NF >= 5 { r = $5 }
        NF == 2 && $1 ~ /^[0-9.]+$/ { g = $2 }
        END { if (r == "" || g == "") exit 1; print r, g }' || {
        echo "then_and_now.sh: the $1 replay bench printed no timing:" >&2
        printf '%s\n' "$out" >&2
        exit 1
    }
}

printf '%-6s %-5s %14s %14s %12s %12s\n' round build "RHS µs (CPU)" "weight µs" "case 1 s" "19 cases s"
declare -A row
ratios=()
for r in $(seq 1 "$rounds"); do
    order=(then now)
    [ $((r % 2)) = 0 ] && order=(now then)
    for which in "${order[@]}"; do
        timings=$(replay "$which")
        run=$(cd "${dir[$which]}" && cpu_of "${kanestop[$which]}" run scenes/paper/case01.toml)
        batch=$(cd "${dir[$which]}" &&
            cpu_of "${kanestop[$which]}" batch scenes/paper --out "$work/batch-$which-$r")
        row[$which]="$timings $run $batch"
        printf '%-6s %-5s %14s %14s %12s %12s\n' "$r" "$which" $timings "$run" "$batch"
    done
    ratios+=("$(python3 -c '
import sys
t, n = ([float(x) for x in a.split()] for a in sys.argv[1:])
print(" ".join(f"{a / b:.2f}x" for a, b in zip(t, n)))' "${row[then]}" "${row[now]}")")
done
echo
echo "then / now per round (RHS, weight alone, case 1 run, 19 cases):"
for r in "${!ratios[@]}"; do echo "  round $((r + 1)): ${ratios[$r]}"; done

if [ "${KANESTOP_CALLGRIND:-0}" = 1 ]; then
    echo
    echo "instructions, kanestop run scenes/paper/case01.toml (valgrind --tool=callgrind):"
    for which in then now; do
        refs=$(cd "${dir[$which]}" && valgrind --tool=callgrind --callgrind-out-file=/dev/null \
            "${kanestop[$which]}" run scenes/paper/case01.toml 2>&1 >/dev/null |
            sed -n 's/.*refs: *\([0-9,]*\).*/\1/p')
        [ -n "$refs" ] || {
            echo "then_and_now.sh: callgrind printed no count for $which" >&2
            exit 1
        }
        echo "  $which $refs"
    done
fi
