#include "epuck_vrep_compat/transport/batch_writer.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <stdexcept>
#include <string>
#include <system_error>

namespace evc {

namespace {
constexpr int kMaxIov = IOV_MAX < 1024 ? IOV_MAX : 1024;
}

BatchWriter::BatchWriter(std::size_t max_backlog_bytes, std::size_t max_backlog_batches)
    : max_backlog_bytes_(max_backlog_bytes), max_backlog_batches_(max_backlog_batches) {
  if (max_backlog_batches_ == 0) {
    throw std::invalid_argument("max_backlog_batches must be at least 1");
  }
}

BatchWriter::~BatchWriter() {
  {
    std::lock_guard<std::mutex> lock(worker_mutex_);
    stopping_ = true;
  }
  worker_wake_.notify_all();
  if (worker_.joinable()) worker_.join();
  for (auto& entry : connections_) {
    if (entry.second.owned) ::close(entry.second.fd);
  }
}

int BatchWriter::open(int fd, bool own) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  if (fd < 0 && !own) {  // fcntl reports it when duplicating; a borrowed one is checked here
    throw std::system_error(EBADF, std::generic_category(),
                            "negative descriptor (a closed socket)");
  }
  const int writer_fd = own ? ::fcntl(fd, F_DUPFD_CLOEXEC, 0) : fd;
  if (writer_fd < 0) throw std::system_error(errno, std::generic_category(), "dup of a socket");
  const int id = next_id_++;  // never reused, unlike descriptors: a late report stays its own
  connections_[id].fd = writer_fd;
  connections_[id].owned = own;
  return id;
}

void BatchWriter::close(int id) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  take_incoming();  // batches queued for it before the close go with it
  auto it = connections_.find(id);
  if (it == connections_.end()) return;
  if (it->second.owned) ::close(it->second.fd);
  connections_.erase(it);
  to_flush_.erase(std::remove(to_flush_.begin(), to_flush_.end(), id), to_flush_.end());
}

void BatchWriter::queue(int id, const char* data, std::size_t size) {
  if (size == 0) return;
  std::lock_guard<std::mutex> lock(incoming_mutex_);
  incoming_at_[id] = incoming_.size();
  incoming_.emplace_back(id, std::string(data, size));
}

void BatchWriter::queue_slices(const char* data, std::size_t size, const Slice* slices,
                               std::size_t count) {
  for (std::size_t k = 0; k < count; ++k) {
    if (slices[k].begin > slices[k].end || slices[k].end > size) {
      throw std::out_of_range("slice " + std::to_string(k) + " [" +
                              std::to_string(slices[k].begin) + ", " +
                              std::to_string(slices[k].end) + ") is outside the " +
                              std::to_string(size) + " bytes given");
    }
  }
  std::lock_guard<std::mutex> lock(incoming_mutex_);
  for (std::size_t k = 0; k < count; ++k) {
    const Slice& slice = slices[k];
    if (slice.begin == slice.end) continue;
    const auto found = incoming_at_.try_emplace(slice.id, incoming_.size());
    if (found.second) incoming_.emplace_back(slice.id, std::string());
    incoming_[found.first->second].second.append(data + slice.begin, slice.end - slice.begin);
  }
}

void BatchWriter::take_incoming() {
  std::vector<std::pair<int, std::string>> incoming;
  {
    std::lock_guard<std::mutex> lock(incoming_mutex_);
    incoming.swap(incoming_);
    incoming_at_.clear();
  }
  for (auto& item : incoming) {
    auto it = connections_.find(item.first);
    if (it == connections_.end()) continue;  // closed since: its batches go with it
    Connection& c = it->second;
    c.size += item.second.size();
    c.batches.push_back(std::move(item.second));
    if (!c.queued) {
      c.queued = true;
      to_flush_.push_back(item.first);
    }
  }
}

std::vector<WriterReport> BatchWriter::flush() {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return flush_locked();
}

void BatchWriter::request_flush() {
  std::lock_guard<std::mutex> lock(worker_mutex_);
  if (!worker_.joinable()) worker_ = std::thread(&BatchWriter::run_worker, this);
  ++requested_;
  worker_wake_.notify_one();
}

std::vector<WriterReport> BatchWriter::take_reports(bool wait) {
  std::unique_lock<std::mutex> lock(worker_mutex_);
  if (wait) worker_idle_.wait(lock, [this] { return requested_ == 0; });
  std::vector<WriterReport> out;
  out.swap(reports_);
  return out;
}

void BatchWriter::run_worker() {
  std::unique_lock<std::mutex> lock(worker_mutex_);
  while (true) {
    worker_wake_.wait(lock, [this] { return stopping_ || requested_ > 0; });
    if (stopping_) return;
    const std::size_t taking = requested_;  // one flush serves every request made so far
    lock.unlock();
    std::vector<WriterReport> done = flush();
    lock.lock();
    reports_.insert(reports_.end(), done.begin(), done.end());
    requested_ -= taking;
    if (requested_ == 0) worker_idle_.notify_all();
  }
}

std::vector<WriterReport> BatchWriter::flush_locked() {
  take_incoming();
  std::vector<WriterReport> reports;
  std::vector<int> still_waiting;
  for (int id : to_flush_) {
    auto it = connections_.find(id);
    if (it == connections_.end()) continue;
    Connection& c = it->second;
    WriterReport report;
    report.id = id;
    c.sent_untaken += send_waiting(c, report);
    if (!report.failed) report.dropped_batches = trim(c);
    c.queued = !c.batches.empty();
    if (c.queued) still_waiting.push_back(id);
    if (report.dropped_batches || report.failed) reports.push_back(report);
  }
  to_flush_.swap(still_waiting);
  return reports;
}

std::size_t BatchWriter::send_waiting(Connection& c, WriterReport& report) {
  std::size_t total = 0;
  while (!c.batches.empty()) {
    iovec iov[kMaxIov];
    int count = 0;
    for (auto it = c.batches.begin(); it != c.batches.end() && count < kMaxIov; ++it, ++count) {
      const std::size_t skip = count == 0 ? c.head_sent : 0;
      iov[count].iov_base = const_cast<char*>(it->data()) + skip;
      iov[count].iov_len = it->size() - skip;
    }
    msghdr msg{};
    msg.msg_iov = iov;
    msg.msg_iovlen = static_cast<std::size_t>(count);
    const ssize_t sent = ::sendmsg(c.fd, &msg, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (sent < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) {
        report.failed = true;
        c.batches.clear();
        c.head_sent = 0;
        c.size = 0;
      }
      return total;
    }
    std::size_t left = static_cast<std::size_t>(sent);
    total += left;
    c.size -= left;
    while (left > 0) {
      const std::size_t head_left = c.batches.front().size() - c.head_sent;
      if (left < head_left) {
        c.head_sent += left;
        return total;  // the socket is full
      }
      left -= head_left;
      c.batches.pop_front();
      c.head_sent = 0;
    }
  }
  return total;
}

std::size_t BatchWriter::trim(Connection& c) {
  std::size_t dropped = 0;
  while ((c.size > max_backlog_bytes_ || c.batches.size() > max_backlog_batches_) &&
         c.batches.size() > 1) {
    auto second = std::next(c.batches.begin());
    c.size -= second->size();
    c.batches.erase(second);
    ++dropped;
  }
  return dropped;
}

std::vector<SentBytes> BatchWriter::take_sent_bytes(bool wait) {
  std::unique_lock<std::mutex> lock(state_mutex_, std::defer_lock);
  std::vector<SentBytes> out;
  if (wait) {
    lock.lock();
  } else if (!lock.try_lock()) {
    return out;  // a flush holds the state: its bytes are counted next time
  }
  for (auto& entry : connections_) {
    if (entry.second.sent_untaken == 0) continue;
    out.push_back({entry.first, entry.second.sent_untaken});
    entry.second.sent_untaken = 0;
  }
  return out;
}

std::size_t BatchWriter::connection_count() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return connections_.size();
}

std::size_t BatchWriter::backlog_bytes() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  std::size_t total = 0;
  for (const auto& entry : connections_) total += entry.second.size;
  return total;
}

}  // namespace evc
