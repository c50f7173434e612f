// A disk that runs out under the page cache, as thin-provisioned storage
// does (root only): a loop device over a sparse image on a small tmpfs.
// Writes into the page cache succeed; their writeback fails once the tmpfs
// is full, and only an fsync (or the next write-out) says so. `skipped` says
// why where the machine cannot make one (no root, no tmpfs, no loop device,
// no mkfs.ext4); the caller skips its test with it.
#pragma once

#include <fcntl.h>
#include <linux/loop.h>
#include <sys/ioctl.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

namespace treedyn::testing {

class LoopOverSmallTmpfs {
 public:
  // An image of `image_mib` on a tmpfs of `tmpfs_size` ("4m"), under `dir`.
  LoopOverSmallTmpfs(const std::filesystem::path& dir, std::uint64_t image_mib, const std::string& tmpfs_size)
      : backing_(dir / "backing") {
    if (geteuid() != 0) {
      skipped = "needs root for a tmpfs and a loop device";
      return;
    }
    std::filesystem::create_directory(backing_);
    if (mount("tmpfs", backing_.c_str(), "tmpfs", 0, ("size=" + tmpfs_size).c_str()) != 0) {
      skipped = std::string("cannot mount a tmpfs here (") + std::strerror(errno) + ")";
      return;
    }
    tmpfs_mounted_ = true;
    image_ = backing_ / "image";
    const int file = open(image_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
    const int control = open("/dev/loop-control", O_RDWR | O_CLOEXEC);
    const int number = control >= 0 ? ioctl(control, LOOP_CTL_GET_FREE) : -1;
    if (control >= 0) close(control);
    if (file < 0 || ftruncate(file, static_cast<off_t>(image_mib << 20)) != 0 || number < 0) {
      skipped = std::string("no loop device here (") + std::strerror(errno) + ")";
      if (file >= 0) close(file);
      return;
    }
    device = "/dev/loop" + std::to_string(number);
    loop_ = open(device.c_str(), O_RDWR | O_CLOEXEC);
    if (loop_ < 0 || ioctl(loop_, LOOP_SET_FD, file) != 0) skipped = "cannot attach " + device + " here";
    close(file);
  }
  ~LoopOverSmallTmpfs() {
    if (!filesystem_.empty()) umount2(filesystem_.c_str(), MNT_DETACH);
    if (loop_ >= 0) {
      ioctl(loop_, LOOP_CLR_FD, 0);
      close(loop_);
    }
    if (tmpfs_mounted_) umount2(backing_.c_str(), MNT_DETACH);
  }
  LoopOverSmallTmpfs(const LoopOverSmallTmpfs&) = delete;
  LoopOverSmallTmpfs& operator=(const LoopOverSmallTmpfs&) = delete;

  // An ext4 file system on the device, mounted at `at`: no journal and lazy
  // tables, so that making it writes little into the tmpfs; errors=continue,
  // so that a failed write-out fails that file, not the mount. Returns
  // false, with `skipped` set, where it cannot be made.
  bool mount_ext4(const std::filesystem::path& at) {
    const std::string mkfs =
        "mkfs.ext4 -q -F -m 0 -O ^has_journal -E lazy_itable_init=1,nodiscard " + device + " > /dev/null 2>&1";
    if (std::system(mkfs.c_str()) != 0) {
      skipped = "cannot make an ext4 file system here (mkfs.ext4)";
      return false;
    }
    std::filesystem::create_directory(at);
    if (mount(device.c_str(), at.c_str(), "ext4", 0, "errors=continue") != 0) {
      skipped = std::string("cannot mount ext4 here (") + std::strerror(errno) + ")";
      return false;
    }
    filesystem_ = at;
    return true;
  }

  std::string device;
  std::string skipped;

 private:
  std::filesystem::path backing_, image_, filesystem_;
  int loop_ = -1;
  bool tmpfs_mounted_ = false;
};

}  // namespace treedyn::testing
