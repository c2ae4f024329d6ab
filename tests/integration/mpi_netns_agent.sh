#!/bin/sh
# Open MPI's launch agent for test_mpi_hosts.py, in place of ssh: mpirun runs
# "AGENT HOST COMMAND..." to start its daemon on HOST. Here a host is a network
# namespace of that name, and the command runs in it as on a machine of its
# own: its own network stack, host name (UTS namespace) and /run (a private
# mount: the IP nodes' namespaces and the run's claim live there). The file
# system beside it is shared, as NFS would be, /tmp included (the clone and
# its build may be there, as in CI).
host=$1
shift
exec ip netns exec "$host" unshare --mount --uts sh -c \
  'hostname "$0" && mount -t tmpfs tmpfs /run && mkdir /run/netns && eval "$*"' "$host" "$@"
