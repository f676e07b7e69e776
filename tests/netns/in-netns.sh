#!/usr/bin/env bash
# in-netns.sh CMD [ARGS...]
#
# Runs CMD in a fresh, private network namespace that holds only a loopback
# interface, with the whole multicast range 224.0.0.0/4 routed to it. LCM's UDP
# multicast (udpm://...) therefore works between processes started inside the
# namespace, and no packet -- not even an IGMP join -- reaches a real network.
#
#   root:     unshare -n
#   non-root: unshare -rn  (a user namespace maps the caller to root, so that
#             the loopback device can be configured; files created keep the
#             caller's ownership outside)
#
# Exit status: that of CMD; 77 (ctest's SKIP_RETURN_CODE) when a private
# network namespace cannot be created here (no unshare/ip, or not permitted,
# e.g. in a container without CAP_SYS_ADMIN or with user namespaces disabled).
set -euo pipefail

if [[ $# -eq 0 || $1 == -h || $1 == --help ]]; then
  echo "usage: $(basename "$0") CMD [ARGS...]   (runs CMD in a private network namespace)" >&2
  [[ $# -eq 0 ]] && exit 2 || exit 0
fi

skip() {
  echo "in-netns.sh: SKIP: $*" >&2
  exit 77
}

command -v unshare >/dev/null 2>&1 || skip "unshare not found (Debian package util-linux)"
command -v ip >/dev/null 2>&1 || skip "ip not found (Debian package iproute2)"

if [[ $(id -u) -eq 0 ]]; then
  flags=(-n)
else
  flags=(-r -n)
fi

# shellcheck disable=SC2016  # expanded by the inner shell, on purpose
setup='ip link set lo up && ip route add 224.0.0.0/4 dev lo'

# Probe first, so that "not permitted" (-> 77) is not confused with CMD's own
# failure. The probe namespace dies with its only process.
if ! probe_err=$(unshare "${flags[@]}" -- /bin/sh -c "$setup" 2>&1); then
  skip "cannot create a private network namespace with 'unshare ${flags[*]}'" \
       "(${probe_err//$'\n'/ }); needs root with CAP_SYS_ADMIN, or unprivileged user namespaces"
fi

exec unshare "${flags[@]}" -- /bin/sh -c "$setup"' || { echo "in-netns.sh: network set-up failed" >&2; exit 77; }
exec "$@"' in-netns "$@"
