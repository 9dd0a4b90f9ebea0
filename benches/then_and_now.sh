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
# Each round runs, alternately then and now: the replayed right-hand side (cases 1, every solve
# of its run through Dynamics) and weight alone at N = 46 (benches/replay.rs), case 1's whole
# `kanestop run`, and the 19 paper cases' `kanestop batch` (CPU time of the process and its
# threads). Prints every measurement and, per round, now / then.
set -euo pipefail

rounds=${1:-3}
base=${KANESTOP_BASELINE:-4cfb922}
here=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'git -C "$here" worktree remove --force "$work/then" >/dev/null 2>&1 || true; rm -rf "$work"' EXIT

git -C "$here" worktree add --detach "$work/then" "$base" >/dev/null 2>&1
cp "$here/benches/replay.rs" "$work/then/benches/replay.rs"
grep -q 'name = "replay"' "$work/then/Cargo.toml" ||
    printf '\n[[bench]]\nname = "replay"\nharness = false\n' >>"$work/then/Cargo.toml"

build() { # DIR -> prints the replay bench's executable
    (cd "$1" && cargo build --release --quiet --bin kanestop &&
        cargo bench --bench replay --no-run --message-format=json 2>/dev/null |
        sed -n 's/.*"executable":"\([^"]*replay-[^"]*\)".*/\1/p' | tail -1)
}
echo "building $base (then) and this checkout (now)…" >&2
then_bench=$(build "$work/then")
now_bench=$(build "$here")

cpu_of() { # command… -> user + system CPU seconds of the command and its threads
    python3 -c '
import resource, subprocess, sys
subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
r = resource.getrusage(resource.RUSAGE_CHILDREN)
print(f"{r.ru_utime + r.ru_stime:.3f}")' "$@"
}

replay() { # DIR BENCH -> "rhs_cpu_us gravity_cpu_us"
    (cd "$1" && "$2" 1 | awk '$1 == "1" && NF == 5 { r = $5 } NF == 2 && $1 ~ /^[0-9.]+$/ { g = $2 } END { print r, g }')
}

printf '%-6s %-5s %14s %14s %12s %12s\n' round build "RHS µs (CPU)" "weight µs" "case 1 s" "19 cases s"
declare -a ratios
for r in $(seq 1 "$rounds"); do
    for which in then now; do
        if [ "$which" = then ]; then dir=$work/then bench=$then_bench; else dir=$here bench=$now_bench; fi
        read -r rhs grav < <(replay "$dir" "$bench")
        run=$(cd "$dir" && cpu_of target/release/kanestop run scenes/paper/case01.toml)
        batch=$(cd "$dir" && cpu_of target/release/kanestop batch scenes/paper --out "$work/batch-$which")
        printf '%-6s %-5s %14s %14s %12s %12s\n' "$r" "$which" "$rhs" "$grav" "$run" "$batch"
        eval "${which}_row=(\$rhs \$grav \$run \$batch)"
    done
    ratios+=("$(python3 -c "
t = [float(x) for x in '${then_row[*]}'.split()]
n = [float(x) for x in '${now_row[*]}'.split()]
print(' '.join(f'{a / b:.2f}x' for a, b in zip(t, n)))")")
done
echo
echo "then / now per round (RHS, weight alone, case 1 run, 19 cases):"
for r in "${!ratios[@]}"; do echo "  round $((r + 1)): ${ratios[$r]}"; done

if [ "${KANESTOP_CALLGRIND:-0}" = 1 ]; then
    echo
    echo "instructions, kanestop run scenes/paper/case01.toml (valgrind --tool=callgrind):"
    for which in then now; do
        if [ "$which" = then ]; then dir=$work/then; else dir=$here; fi
        (cd "$dir" && valgrind --tool=callgrind --callgrind-out-file=/dev/null \
            target/release/kanestop run scenes/paper/case01.toml 2>&1 >/dev/null |
            sed -n "s/.*refs: *\([0-9,]*\).*/  $which \1/p")
    done
fi
