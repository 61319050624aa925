# Sourced by .ci/run, .ci/setup.sh and .ci/libfuzzer.sh. install_missing PACKAGE... installs those
# of the Debian packages named that are not installed yet (with sudo unless root); installed ones
# are skipped, so running again costs nothing.
install_missing() {
  local missing=() p sudo=""
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  ((${#missing[@]})) || return 0
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq &&
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}
