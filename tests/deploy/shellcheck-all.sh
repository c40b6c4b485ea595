#!/usr/bin/env bash
# Usage: shellcheck-all.sh ROOT. Lints every shell script under ROOT's deploy/, scripts/, .ci/
# (by extension .sh/.bash/.sbatch, or by a sh/bash shebang), found when the test runs.
set -euo pipefail
root=$1
scripts=()
while IFS= read -r -d '' file; do
    case "$file" in
    *.sh | *.bash | *.sbatch) scripts+=("$file") ;;
    *) head -n 1 "$file" | grep -Eq '^#!.*[/ ](ba)?sh( |$)' && scripts+=("$file") ;;
    esac
done < <(find "$root/deploy" "$root/scripts" "$root/.ci" -type f -print0 2>/dev/null | sort -z)
if [[ ${#scripts[@]} -eq 0 ]]; then
    echo "shellcheck-all.sh: no shell scripts found under $root" >&2
    exit 1
fi
printf 'shellcheck: %s\n' "${scripts[@]#"$root"/}"
shellcheck --external-sources "${scripts[@]}"
