# Sourced by the FMU shell tests (fmu_ramps_test.sh, fmu_study_test.sh) after
# node_start.bash: the scenes and mappings they share.
#   fail MESSAGE [FILE]        print, show FILE, exit 1
#   soil_scene OUT             scenes/soil.toml for 0.05 s, one rate, 10 micro steps
#   soil_mapping FMU           the lumped soil FMU's mapping (a [soil] table's keys)
#   mapped_soil_scene FMU OUT  soil_scene with its [soil] table mapped onto FMU
#                              (model = "external")
fail() {
  echo "$1"
  [[ -z ${2:-} ]] || cat "$2"
  exit 1
}
soil_scene() {
  sed -e 's/^end_time = .*/end_time = 0.05/' -e '/^ss_macro_step/d' \
    -e 's/^\(tolerance = .*\)/\1\nmicro_steps = 10/' "$src/scenes/soil.toml" >"$1"
  grep -q '^micro_steps = 10' "$1" || fail "the scene was not edited"
}
soil_mapping() {
  cat <<TOML
file = "$bin/fmus/$1"
ss_in_displacement = "w_{i}"
ss_in_velocity = "wd_{i}"
ss_out_displacement = "u_{i}"
ss_out_velocity = "ud_{i}"
set_micro_steps = 10
peak_history = "soil_peak_m"
result_soil_m = "u_{i}"
TOML
}
mapped_soil_scene() {
  soil_scene "$work/plain.toml"
  soil_mapping "$1" >"$work/map.toml"
  awk -v fmu="$work/map.toml" '
    /^\[soil\]/ { print; print "model = \"external\""
                  while ((getline line < fmu) > 0) print line
                  skip = 1; next }
    /^\[/ { skip = 0 }
    !skip { print }' "$work/plain.toml" >"$2"
  grep -q '^model = "external"' "$2" || fail "the scene was not written"
}
