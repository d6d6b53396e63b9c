# Sourced by the sweep scripts (sweep_parallel.sh, sweep_inertial.sh), which define fail().
# same_files DIR_A DIR_B GLOB: every file of DIR_A matching GLOB equals the file of the same name in
# DIR_B byte for byte (fail names the first that differs); prints how many were compared (0 when none
# matches, so the caller's count check catches a missing set).
same_files() {
	local a=$1 b=$2 glob=$3 n=0 f
	for f in "$a"/$glob; do
		[ -e "$f" ] || continue
		cmp "$f" "$b/$(basename "$f")" >&2 || fail "$(basename "$f") differs"
		n=$((n + 1))
	done
	echo "$n"
}
