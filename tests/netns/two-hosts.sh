# two-hosts.sh: two "computers" joined by a network cable, for multi-host tests. Sourced (after
# `set -euo pipefail`) by a script that already runs in a private network namespace
# (tests/netns/in-netns.sh): that namespace is host A, the robot's pilot computer; a second
# namespace is made for host B, the navigator's computer; a veth pair is the cable.
#
#   A: bridge br-robot (169.254.67.1/24, multicast route 224.0.0.0/4) with the port veth-a
#   B: veth-b (169.254.67.2/24, multicast route 224.0.0.0/4)
# Link-local addresses inside our own namespaces: nothing is routed anywhere else. LCM uses
# ttl=1 (one hop: across the cable, no further).
#
# Why a bridge on A (measured; README "Deploying on two computers"): LCM joins its multicast group
# on the interface of the multicast route. If that interface itself is set down, the kernel
# drops the route and the memberships, and the processes on A stop hearing *each other*. With
# the port in a bridge, "ip link set veth-a down" pulls only the port: the bridge, its route and
# memberships stay, and A's own traffic goes on. (IGMP snooping off: after the port comes back,
# a snooping bridge would forward the group to B only once B re-reported its membership.)
#
# Functions: twohosts_up, in_b CMD..., link_cut, link_restore, twohosts_down (also on EXIT via
# the caller's cleanup: call it there). Sets host_b_pid. For a background process in B use
# `nsenter -t "$host_b_pid" -n CMD &` (not `in_b CMD &`), so that $! is CMD itself.

host_b_pid=
twohosts_up() {
  unshare -n sleep 100000 &
  host_b_pid=$!
  local i
  for i in $(seq 50); do
    [[ $(readlink /proc/$host_b_pid/ns/net) != "$(readlink /proc/self/ns/net)" ]] && break
    sleep 0.02
  done
  ip link add veth-a type veth peer name veth-b netns "$host_b_pid"
  ip link add br-robot type bridge mcast_snooping 0 stp_state 0
  ip link set veth-a master br-robot
  ip addr add 169.254.67.1/24 dev br-robot
  ip link set br-robot up
  ip link set veth-a up
  ip route del 224.0.0.0/4 dev lo 2>/dev/null || true
  ip route add 224.0.0.0/4 dev br-robot
  in_b sh -c 'ip link set lo up && ip addr add 169.254.67.2/24 dev veth-b && ip link set veth-b up &&
              ip route add 224.0.0.0/4 dev veth-b'
  # The cable is up when both ends have a carrier.
  for i in $(seq 100); do
    ip -o link show br-robot | grep -q LOWER_UP && in_b ip -o link show veth-b | grep -q LOWER_UP && return 0
    sleep 0.05
  done
  echo "two-hosts.sh: the link between A and B did not come up" >&2
  return 1
}
in_b() { nsenter -t "$host_b_pid" -n "$@"; }
link_cut() { ip link set veth-a down; }
link_restore() { ip link set veth-a up; }
twohosts_down() {
  [[ -n $host_b_pid ]] && kill "$host_b_pid" 2>/dev/null || true
  host_b_pid=
}
