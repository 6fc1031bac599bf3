# shellcheck shell=bash
# Sourced by the scripts that install Debian 12 packages (scripts/setup.sh,
# bench/render_assets.sh):
#   as_root COMMAND...                   runs COMMAND as root (sudo unless root)
#   install_missing_packages WHO PKG...  installs, without recommends, the PKGs
#                                        dpkg does not list as installed, and
#                                        says so as "WHO: installing ..."

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

install_missing_packages() {
  local who=$1 p
  shift
  local missing=()
  for p in "$@"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "$who: installing ${missing[*]}"
    as_root apt-get update -qq
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
}
