#include "fake_v4l2_device.hpp"

#include <linux/videodev2.h>
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>

namespace vigs::drivers::testing {
namespace {

constexpr std::uint32_t kPage = 4096;

std::uint32_t page_round(std::uint32_t n) {
  return (n + kPage - 1) / kPage * kPage;
}

}  // namespace

void FakeV4l2Device::add_node(const std::string& path, const FakeNodeSpec& spec) {
  std::lock_guard lock(mutex_);
  nodes_[path].spec = spec;
}

void FakeV4l2Device::notify() {
  cv_.notify_all();
}

bool FakeV4l2Device::push_frame(const std::string& path, const FakeFrame& f) {
  bool delivered = false;
  {
    std::lock_guard lock(mutex_);
    Node& n = nodes_.at(path);
    n.sequence += f.skip_sequence;
    const std::uint32_t seq = n.sequence++;
    if (n.present && n.streaming && !n.queued.empty()) {
      const std::uint32_t i = n.queued.front();
      n.queued.erase(n.queued.begin());
      Buffer& b = *n.buffers[i];
      const std::size_t len = std::min(f.bytes.size(), b.memory.size());
      std::memcpy(b.memory.data(), f.bytes.data(), len);
      b.bytes_used = static_cast<std::uint32_t>(len);
      b.sequence = seq;
      b.t_ns = f.t_ns;
      b.flags =
          V4L2_BUF_FLAG_MAPPED | V4L2_BUF_FLAG_DONE |
          (f.monotonic_flag ? V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC : V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN) |
          (f.error_flag ? V4L2_BUF_FLAG_ERROR : 0u);
      b.state = BufState::kDone;
      n.done.push_back(i);
      delivered = true;
    }
  }
  notify();
  return delivered;
}

void FakeV4l2Device::unplug(const std::string& path) {
  {
    std::lock_guard lock(mutex_);
    nodes_.at(path).present = false;
  }
  notify();
}

void FakeV4l2Device::spurious_wakeups(const std::string& path, int count) {
  {
    std::lock_guard lock(mutex_);
    nodes_.at(path).spurious = count;
  }
  notify();
}

void FakeV4l2Device::replug(const std::string& path) {
  std::lock_guard lock(mutex_);
  Node& n = nodes_.at(path);
  // A new device instance: nothing of the old one survives.
  Node fresh;
  fresh.spec = n.spec;
  fresh.opens = n.opens;
  fresh.generation = n.generation + 1;
  n = std::move(fresh);
}

std::size_t FakeV4l2Device::queued(const std::string& path) {
  std::lock_guard lock(mutex_);
  return nodes_.at(path).queued.size();
}

bool FakeV4l2Device::streaming(const std::string& path) {
  std::lock_guard lock(mutex_);
  return nodes_.at(path).streaming;
}

int FakeV4l2Device::opens(const std::string& path) {
  std::lock_guard lock(mutex_);
  return nodes_.at(path).opens;
}

int FakeV4l2Device::fail(int err) {
  errno = err;
  return -1;
}

FakeV4l2Device::Node* FakeV4l2Device::node_of(int fd, bool* stale) {
  auto it = fds_.find(fd);
  if (it == fds_.end()) return nullptr;
  Node& n = nodes_.at(it->second.path);
  if (stale != nullptr) *stale = it->second.generation != n.generation;
  return &n;
}

int FakeV4l2Device::open(const char* path) {
  std::lock_guard lock(mutex_);
  auto it = nodes_.find(path);
  if (it == nodes_.end() || !it->second.present) return fail(ENOENT);
  ++it->second.open_count;
  ++it->second.opens;
  fds_[next_fd_] = {path, it->second.generation};
  return next_fd_++;
}

int FakeV4l2Device::close(int fd) {
  std::lock_guard lock(mutex_);
  bool stale = false;
  Node* n = node_of(fd, &stale);
  if (n == nullptr) return fail(EBADF);
  if (!stale &&
      --n->open_count == 0) {  // last close: the kernel stops streaming and frees the buffers
    n->streaming = false;
    n->buffers.clear();
    n->queued.clear();
    n->done.clear();
  }
  fds_.erase(fd);
  return 0;
}

int FakeV4l2Device::ioctl(int fd, unsigned long request, void* arg) {
  std::lock_guard lock(mutex_);
  bool stale = false;
  Node* n = node_of(fd, &stale);
  if (n == nullptr) return fail(EBADF);
  if (!n->present || stale) return fail(ENODEV);
  return ioctl_locked(*n, request, arg);
}

int FakeV4l2Device::ioctl_locked(Node& n, unsigned long request, void* arg) {
  const FakeNodeSpec& s = n.spec;
  switch (request) {
    case VIDIOC_QUERYCAP: {
      auto* c = static_cast<v4l2_capability*>(arg);
      *c = {};
      std::strncpy(reinterpret_cast<char*>(c->driver), "vigs_fake", sizeof c->driver - 1);
      std::strncpy(reinterpret_cast<char*>(c->card), "fake capture", sizeof c->card - 1);
      c->device_caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
      c->capabilities = c->device_caps | V4L2_CAP_DEVICE_CAPS;
      return 0;
    }
    case VIDIOC_ENUM_FMT: {
      auto* f = static_cast<v4l2_fmtdesc*>(arg);
      if (f->index != 0 || f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return fail(EINVAL);
      f->pixelformat = s.pixelformat;
      f->flags = s.pixelformat == V4L2_PIX_FMT_MJPEG ? V4L2_FMT_FLAG_COMPRESSED : 0;
      std::strncpy(reinterpret_cast<char*>(f->description), "fake", sizeof f->description - 1);
      return 0;
    }
    case VIDIOC_ENUM_FRAMESIZES: {
      auto* f = static_cast<v4l2_frmsizeenum*>(arg);
      if (f->index != 0 || f->pixel_format != s.pixelformat) return fail(EINVAL);
      f->type = V4L2_FRMSIZE_TYPE_DISCRETE;
      f->discrete = {s.width, s.height};
      return 0;
    }
    case VIDIOC_G_FMT:
    case VIDIOC_S_FMT:
    case VIDIOC_TRY_FMT: {
      auto* f = static_cast<v4l2_format*>(arg);
      if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return fail(EINVAL);
      if (request == VIDIOC_S_FMT && !n.buffers.empty()) return fail(EBUSY);
      f->fmt.pix.width = s.width;  // the node adjusts the request to what it has
      f->fmt.pix.height = s.height;
      f->fmt.pix.pixelformat = s.pixelformat;
      f->fmt.pix.field = V4L2_FIELD_NONE;
      f->fmt.pix.bytesperline = s.bytes_per_line;
      f->fmt.pix.sizeimage = s.size_image;
      return 0;
    }
    case VIDIOC_S_PARM:
    case VIDIOC_G_PARM:
      return 0;
    case VIDIOC_REQBUFS: {
      auto* r = static_cast<v4l2_requestbuffers*>(arg);
      if (r->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || r->memory != V4L2_MEMORY_MMAP) {
        return fail(EINVAL);
      }
      if (n.streaming) return fail(EBUSY);
      n.buffers.clear();
      n.queued.clear();
      n.done.clear();
      r->count = std::min(r->count, s.max_buffers);
      for (std::uint32_t i = 0; i < r->count; ++i) {
        n.buffers.push_back(std::make_unique<Buffer>());
        n.buffers.back()->memory.assign(page_round(s.size_image), 0);
      }
      return 0;
    }
    case VIDIOC_QUERYBUF:
    case VIDIOC_QBUF:
    case VIDIOC_DQBUF: {
      auto* b = static_cast<v4l2_buffer*>(arg);
      if (b->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || b->memory != V4L2_MEMORY_MMAP) {
        return fail(EINVAL);
      }
      if (request == VIDIOC_DQBUF) {
        if (!n.streaming) return fail(EINVAL);
        if (n.done.empty()) return fail(EAGAIN);
        b->index = n.done.front();
        n.done.erase(n.done.begin());
      } else if (b->index >= n.buffers.size()) {
        return fail(EINVAL);
      }
      Buffer& buf = *n.buffers[b->index];
      if (request == VIDIOC_QBUF) {
        if (buf.state != BufState::kUser) return fail(EINVAL);
        buf.state = BufState::kQueued;
        n.queued.push_back(b->index);
        return 0;
      }
      if (request == VIDIOC_DQBUF) buf.state = BufState::kUser;
      b->length = static_cast<std::uint32_t>(buf.memory.size());
      b->m.offset = b->index * page_round(s.size_image);
      b->bytesused = buf.bytes_used;
      b->sequence = buf.sequence;
      b->flags = buf.flags;
      b->field = V4L2_FIELD_NONE;
      b->timestamp.tv_sec = buf.t_ns / 1'000'000'000;
      b->timestamp.tv_usec = (buf.t_ns % 1'000'000'000) / 1000;
      return 0;
    }
    case VIDIOC_STREAMON:
      if (n.buffers.empty()) return fail(EINVAL);
      n.streaming = true;
      return 0;
    case VIDIOC_STREAMOFF:
      n.streaming = false;
      for (auto& b : n.buffers) b->state = BufState::kUser;
      n.queued.clear();
      n.done.clear();
      return 0;
    default:
      return fail(EINVAL);  // ENOTTY on a real node; libv4lconvert treats both as "no"
  }
}

void* FakeV4l2Device::mmap(std::size_t length, int fd, off_t offset) {
  std::lock_guard lock(mutex_);
  bool stale = false;
  Node* n = node_of(fd, &stale);
  if (n == nullptr) {
    errno = EBADF;
    return MAP_FAILED;
  }
  if (!n->present || stale) {
    errno = ENODEV;
    return MAP_FAILED;
  }
  const std::uint32_t step = page_round(n->spec.size_image);
  const auto index = static_cast<std::size_t>(offset) / step;
  if (static_cast<std::size_t>(offset) % step != 0 || index >= n->buffers.size() ||
      length > n->buffers[index]->memory.size()) {
    errno = EINVAL;
    return MAP_FAILED;
  }
  return n->buffers[index]->memory.data();
}

int FakeV4l2Device::munmap(void*, std::size_t) {
  return 0;
}

int FakeV4l2Device::poll(pollfd* fds, nfds_t count, int timeout_ms) {
  std::unique_lock lock(mutex_);
  const auto ready = [&] {
    int r = 0;
    for (nfds_t i = 0; i < count; ++i) {
      fds[i].revents = 0;
      bool stale = false;
      Node* n = node_of(fds[i].fd, &stale);
      if (n == nullptr) {
        fds[i].revents = POLLNVAL;
      } else if (!n->present || stale) {
        fds[i].revents = POLLERR | POLLHUP;
      } else if (!n->streaming) {
        fds[i].revents = POLLERR;
      } else if (!n->done.empty()) {
        fds[i].revents = POLLIN | POLLRDNORM;
      } else if (n->spurious > 0) {
        --n->spurious;
        fds[i].revents = POLLIN | POLLRDNORM;
      }
      r += fds[i].revents != 0;
    }
    return r;
  };
  int r = 0;
  cv_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [&] { return (r = ready()) > 0; });
  return r;
}

}  // namespace vigs::drivers::testing
