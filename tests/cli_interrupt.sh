#!/bin/sh
# Ctrl-C during `tumble run`: SIGINT sent once the output (the CSV, or the writer's side file)
# is there, mid-run; tumble must end by SIGINT (a shell's 130) and leave no file in DIR, where
# nothing else is. The run (RK4 at 1 us for 600 s of the Dzhanibekov scene) would take an hour
# (9 s for 12 s on a 2-core Xeon), so the signal always lands during it; waiting for the file,
# not for a time, makes it certain the handler is installed.
#   cli_interrupt.sh TUMBLE SCENE DIR EXTENSION
# A shell starts a background job with SIGINT ignored, which tumble keeps (as it should under
# nohup): GNU env (coreutils 8.31 or later) gives it back its default; without it the test is
# skipped (77).
tumble=$1 scene=$2 dir=$3 extension=$4
if ! env --default-signal=INT true 2>/dev/null; then
    echo "cli_interrupt: env --default-signal is not there (GNU coreutils >= 8.31): skipped"
    exit 77
fi
rm -rf "$dir"
mkdir -p "$dir"
env --default-signal=INT "$tumble" run "$scene" --integrator rk4 --dt 1e-6 --duration 600 --out "$dir/out.$extension" \
    2>"$dir.stderr" &
pid=$!
tries=0
while [ -z "$(ls -A "$dir")" ]; do
    tries=$((tries + 1))
    if [ $tries -gt 600 ]; then
        kill -KILL $pid
        echo "cli_interrupt: no output in $dir after 60 s" >&2
        exit 1
    fi
    sleep 0.1
done
kill -INT $pid
wait $pid
code=$?
cat "$dir.stderr" >&2
if [ $code -ne 130 ]; then
    echo "cli_interrupt: exit status $code, expected 130 (ended by SIGINT)" >&2
    exit 1
fi
left=$(ls -A "$dir")
if [ -n "$left" ]; then
    echo "cli_interrupt: left behind in $dir: $left" >&2
    exit 1
fi
grep -q "interrupted, nothing written to $dir/out.$extension" "$dir.stderr" || exit 1
echo "cli_interrupt: .$extension: ended by SIGINT, nothing left"
