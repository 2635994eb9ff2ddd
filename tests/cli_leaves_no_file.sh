#!/bin/sh
# Runs `tumble run SCENE --out OUT` with no OUT there before, passes its exit code on, and
# fails (9) if OUT, or a side file OUT.*, is there after.
#   cli_leaves_no_file.sh TUMBLE SCENE OUT
rm -f "$3"
"$1" run "$2" --out "$3"
code=$?
for left in "$3" "$3".*; do
    if [ -e "$left" ]; then
        echo "cli_leaves_no_file: $left is left behind" >&2
        exit 9
    fi
done
exit $code
