#!/usr/bin/env bash
# Mutation check of the estimator core: applies each mutation of tests/mutations/mutations.txt to a
# copy of the committed tree (HEAD), rebuilds, runs the tests named for it and expects at least one
# to fail ("killed"). Prints one line per mutation and exits 1 if any survives, or if a named test
# already fails without its mutation. On demand, not part of CI (each mutation is a rebuild):
#   scripts/mutation-check.sh [ID ...]      all mutations, or only those IDs
# Work directory: build-mutation/ (a copy of HEAD and its build; reused between runs: a rerun rebuilds
# only what differs from the last one's tree).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
list=tests/mutations/mutations.txt
work=$root/build-mutation
src=$work/src
jobs=$(nproc 2>/dev/null || echo 2)

# The copy is brought to HEAD file by file: only a file whose content differs is rewritten (and so
# rebuilt), so a rerun reuses the objects of the last one. A mutated file left by an interrupted run
# differs from HEAD and is rewritten; a restored one was touched when it was restored.
head_tree=$work/head
rm -rf "$head_tree" && mkdir -p "$head_tree" "$src"
git archive HEAD | tar -x -C "$head_tree"
(cd "$head_tree" && find . -type f) | while IFS= read -r f; do
	cmp -s "$head_tree/$f" "$src/$f" && continue
	mkdir -p "$(dirname "$src/$f")" && cp "$head_tree/$f" "$src/$f" && touch "$src/$f"
done
(cd "$src" && find . -type f) | while IFS= read -r f; do [ -e "$head_tree/$f" ] || rm -f "$src/$f"; done
cmake -S "$src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DSWBA_BUILD_BENCH=OFF >/dev/null

build() { cmake --build "$work/build" -j "$jobs" >"$work/build.log" 2>&1; }
# run_tests REGEX -> prints the failed test names, returns ctest's status
run_tests() {
	local out
	out=$(ctest --test-dir "$work/build" -j "$jobs" -R "$1" 2>&1) && return 0
	echo "$out" | sed -n 's/^[[:space:]]*[0-9]* - \(.*\) (Failed)$/\1/p' | tr '\n' ' '
	return 1
}
# apply FILE BEFORE AFTER: replaces the one occurrence of BEFORE (fixed text) by AFTER
apply() {
	FILE="$1" BEFORE="$2" AFTER="$3" perl -0777 -i -pe '
		my $n = () = /\Q$ENV{BEFORE}\E/g;
		die "mutation text found $n times in $ENV{FILE} (need exactly 1)\n" if $n != 1;
		s/\Q$ENV{BEFORE}\E/$ENV{AFTER}/;' "$1"
}

declare -a ids files befores afters kills
id="" file="" before="" after="" kill=""
flush() {
	[ -z "$id" ] && return 0
	ids+=("$id") files+=("$file") befores+=("$before") afters+=("$after") kills+=("$kill")
	id="" file="" before="" after="" kill=""
}
while IFS= read -r line || [ -n "$line" ]; do
	case "$line" in
	'#'*) ;;
	'') flush ;;
	id:*) id=${line#id:} id=${id# } ;;
	file:*) file=${line#file:} file=${file# } ;;
	before:*) before=${line#before:} before=${before# } ;;
	after:*) after=${line#after:} after=${after# } ;;
	kill:*) kill=${line#kill:} kill=${kill# } ;;
	*) echo "$list: cannot read line: $line" >&2; exit 2 ;;
	esac
done <"$list"
flush

wanted=" $* "
echo "mutation-check: ${#ids[@]} mutations in $list; building the unmutated tree" >&2
build || { echo "mutation-check: the unmutated tree does not build (see $work/build.log)" >&2; exit 2; }
all=$(IFS='|'; echo "${kills[*]}")
if ! failed=$(run_tests "$all"); then
	echo "mutation-check: tests fail without any mutation: $failed" >&2
	exit 2
fi
status=0
for i in "${!ids[@]}"; do
	[ $# -gt 0 ] && [[ $wanted != *" ${ids[$i]} "* ]] && continue
	f=$src/${files[$i]}
	cp "$f" "$f.orig"
	if ! apply "$f" "${befores[$i]}" "${afters[$i]}"; then
		mv "$f.orig" "$f"
		status=1
		continue
	fi
	if ! build; then
		printf '%-34s KILLED    (does not compile)\n' "${ids[$i]}"
	elif failed=$(run_tests "${kills[$i]}"); then
		printf '%-34s SURVIVED  %s\n' "${ids[$i]}" "${kills[$i]}"
		status=1
	else
		printf '%-34s KILLED    by %s\n' "${ids[$i]}" "$failed"
	fi
	touch "$f.orig" && mv "$f.orig" "$f"  # newer than the mutated object: the next build restores it
done
exit $status
