// The one write of the .geo mesher's socket protocol: shared by the
// mesher's client (Mesh.cpp) and the .geo mesher helper (GeoMesher.cpp).
#pragma once

#include <sys/socket.h>
#include <sys/types.h>

#include <cerrno>
#include <string>

namespace cms::mesh::detail {

/// Writes all of `s` to the socket `fd` (retrying after signals, never
/// raising SIGPIPE); false when the other end has gone.
inline bool sendAll(int fd, const std::string& s) {
  for (std::size_t done = 0; done < s.size();) {
    const ssize_t n = ::send(fd, s.data() + done, s.size() - done, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace cms::mesh::detail
