#pragma once
/// Named Linux network namespaces, made the way `ip netns add` makes them (a
/// namespace file bind-mounted onto /run/netns/NAME), so that `ip netns list`
/// and `ip netns exec NAME ...` see and enter the emulator's namespaces. Only
/// syscalls: nothing here runs the `ip` program.
#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace rfsitl::ip {

/// Where iproute2 keeps named network namespaces.
inline constexpr const char* kNetnsDir = "/run/netns";

/// A named network namespace, held through an open file descriptor. Owned ones
/// (create) are removed by the destructor (umount2 MNT_DETACH + unlink of the
/// /run/netns file); attached ones (attach, attach_pid) are only closed. The
/// kernel keeps a namespace alive while anything still refers to it (a
/// process, an open socket or TAP device in it), even after its name is gone.
/// Not copyable; the const members may be used from any thread at once.
class NetworkNamespace {
 public:
  /// Makes a new, empty network namespace named `name` (only a loopback,
  /// down). Needs CAP_SYS_ADMIN. Throws std::invalid_argument for a name that
  /// is not a plain file name, std::system_error naming the namespace, the step
  /// and the reason when it exists already or a step fails; then nothing of it
  /// is left behind. The calling thread's namespace does not change.
  static NetworkNamespace create(const std::string& name);

  /// The existing namespace /run/netns/NAME (made by create, or by `ip netns
  /// add`), not owned. Throws std::system_error naming it when it is missing
  /// or is not a network namespace.
  static NetworkNamespace attach(const std::string& name);

  /// The network namespace of process `pid` (/proc/PID/ns/net), not owned;
  /// its name() is "pid:PID". Throws std::system_error naming the pid.
  static NetworkNamespace attach_pid(int pid);

  NetworkNamespace(NetworkNamespace&& other) noexcept;
  /// Removes (owned) or closes (attached) the namespace held so far first.
  NetworkNamespace& operator=(NetworkNamespace&& other) noexcept;
  NetworkNamespace(const NetworkNamespace&) = delete;
  NetworkNamespace& operator=(const NetworkNamespace&) = delete;
  /// remove() for owned ones, errors ignored (a destructor cannot report them).
  ~NetworkNamespace();

  const std::string& name() const { return name_; }
  bool owned() const { return owned_; }
  /// An O_RDONLY | O_CLOEXEC descriptor of the namespace, owned by this object
  /// (do not close it); -1 after remove() or a move.
  int fd() const { return fd_; }

  /// Runs fn() on a short-lived std::thread that has setns()'d into this
  /// namespace, joins it and returns fn's result (by value) or rethrows its
  /// exception. Sockets, TAP devices and /proc/sys/net files opened by fn
  /// belong to this namespace and stay so when used from other threads later.
  /// The calling thread's namespace never changes. fn may capture by reference:
  /// it has finished when this returns. Throws std::system_error naming the
  /// namespace when the thread cannot enter it (e.g. after remove()).
  template <typename F>
  auto run_inside(F&& fn) const;

  /// For owned ones: closes the descriptor, unmounts and deletes
  /// /run/netns/NAME. Idempotent; does nothing for attached ones (see
  /// remove_namespace). Throws std::system_error naming the namespace when the
  /// file cannot be deleted (the object then counts as removed all the same).
  void remove();

 private:
  NetworkNamespace(std::string name, int fd, bool owned);
  /// What the destructor does: remove() or close, never throwing.
  void drop() noexcept;
  void run_on_thread_inside(const std::function<void()>& body) const;

  std::string name_;
  int fd_ = -1;
  bool owned_ = false;
};

/// Whether /run/netns/NAME exists (what `ip netns list` shows). Any thread.
bool namespace_exists(const std::string& name);

/// The names in /run/netns that start with `prefix`, sorted; empty when the
/// directory does not exist. Any thread.
std::vector<std::string> namespaces_with_prefix(const std::string& prefix);

/// Removes the named namespace whoever made it (a stale one of a run that was
/// killed): detaches its mount and deletes /run/netns/NAME. Nothing to do when
/// it is not there. Throws std::system_error naming it when it cannot be
/// deleted. A namespace still used by a process lives on, without its name.
void remove_namespace(const std::string& name);

template <typename F>
auto NetworkNamespace::run_inside(F&& fn) const {
  using Result = std::invoke_result_t<F&>;
  if constexpr (std::is_void_v<Result>) {
    run_on_thread_inside([&fn] { fn(); });
  } else {
    std::optional<std::remove_cvref_t<Result>> result;
    run_on_thread_inside([&fn, &result] { result.emplace(fn()); });
    return std::move(*result);
  }
}

}  // namespace rfsitl::ip
