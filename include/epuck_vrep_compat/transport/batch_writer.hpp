// BatchWriter: the per-step send path of the ROS faces, off the Python interpreter.
//
// Each subscriber connection (one TCP socket per topic and subscriber, as TCPROS has it) gets
// the bytes of one or more whole message batches per flush. A flush never blocks: each
// connection's socket takes what it accepts now (one sendmsg over every waiting batch); the
// rest waits in that connection's backlog, retried at the next flush. When a backlog holds
// more than max_backlog_bytes, or more than max_backlog_batches batches, its oldest whole
// batches after the head are dropped (never a partly sent one), so a stalled reader loses whole
// messages and never blocks the others. The batch limit bounds what a reader that keeps up
// only in part costs: thousands of small-message connections each a little behind would
// otherwise each hold max_backlog_bytes (gigabytes in all), and data ever older.
//
// A connection is opened on its own duplicate of the socket descriptor (dup; closed by close(),
// so a descriptor the caller closes and the system reuses never receives stale bytes), or on the
// caller's descriptor (borrowed: no extra descriptor, but the caller must close() the connection
// here before it closes the descriptor; close() waits for a flush under way). No Python, no ROS:
// the binding releases the GIL while flushing.
//
// Flushing runs on the caller's thread (flush()) or on the writer's own thread
// (request_flush(), then take_reports()): the caller queues the next batches while the last
// ones are being sent. queue() never waits for a flush; open() and close() wait for the one
// under way. Every method may be called from any thread.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

namespace evc {

/// What went wrong for one connection in one flush (only connections where something did; the
/// bytes sent are counted apart, BatchWriter::take_sent_bytes, so that a flush of thousands of
/// connections reports nothing when all is well).
struct WriterReport {
  int id = -1;                      ///< the connection's id (from BatchWriter::open)
  std::size_t dropped_batches = 0;  ///< whole batches dropped from its backlog
  bool failed = false;              ///< the socket failed (not "full"): the caller drops it
};

/// Bytes one connection's socket took since they were last taken.
struct SentBytes {
  int id = -1;
  std::size_t bytes = 0;
};

/// Non-blocking, batched writes to many sockets with bounded per-connection backlogs.
class BatchWriter {
 public:
  /// A backlog keeps at most max_backlog_bytes and at most max_backlog_batches batches (each
  /// at least 1; the head, perhaps partly sent, is always kept).
  explicit BatchWriter(std::size_t max_backlog_bytes,
                       std::size_t max_backlog_batches = static_cast<std::size_t>(-1));
  ~BatchWriter();
  BatchWriter(const BatchWriter&) = delete;
  BatchWriter& operator=(const BatchWriter&) = delete;

  /// Starts writing to socket descriptor fd, duplicated when own (else borrowed); returns the
  /// connection's id (ids are never reused). Throws std::system_error when the descriptor
  /// cannot be duplicated (EMFILE past the descriptor limit) or is negative (EBADF: a socket
  /// closed before it was handed over), duplicated or borrowed.
  int open(int fd, bool own = true);
  /// Forgets a connection: its backlog goes, its duplicate descriptor is closed.
  void close(int id);
  /// Queues one whole batch for a connection (copied); never waits for a flush. Batches for
  /// an id that is closed (or unknown) by the time they are sent are dropped.
  void queue(int id, const char* data, std::size_t size);
  /// Bytes [begin, end) of a buffer, for one connection.
  struct Slice {
    int id;
    std::size_t begin;
    std::size_t end;
  };
  /// Queues slices of one buffer (copied), for many connections at once (a step's messages of
  /// one kind, each to the connections of its topic). Until the next flush takes them, what is
  /// queued for one connection, by queue() or here, grows one batch in call order. Throws
  /// std::out_of_range, before queueing anything, for a slice outside the buffer.
  void queue_slices(const char* data, std::size_t size, const Slice* slices, std::size_t count);
  /// Sends what every socket takes now, trims backlogs; never blocks on a socket.
  std::vector<WriterReport> flush();
  /// Asks the writer's thread (started on first use) for a flush of what is queued now.
  void request_flush();
  /// The reports of the flushes the writer's thread finished since the last call; with
  /// wait, first waits until every requested flush is done.
  std::vector<WriterReport> take_reports(bool wait);
  /// The bytes each open connection's socket took since the last call that returned them
  /// (connections that took none are left out). With wait, it waits for a flush under way;
  /// without, it returns nothing during one (the bytes are kept for the next call).
  std::vector<SentBytes> take_sent_bytes(bool wait);

  std::size_t backlog_bytes() const;  ///< bytes waiting in every backlog
  std::size_t connection_count() const;
  std::size_t max_backlog_bytes() const { return max_backlog_bytes_; }
  std::size_t max_backlog_batches() const { return max_backlog_batches_; }

 private:
  struct Connection {
    int fd = -1;
    bool owned = true;                ///< fd is the writer's duplicate, closed by close()
    std::deque<std::string> batches;  ///< whole batches, the head maybe partly sent
    std::size_t head_sent = 0;        ///< bytes of the head already sent
    std::size_t size = 0;             ///< unsent bytes in batches
    bool queued = false;              ///< has work in this flush
    std::size_t sent_untaken = 0;     ///< bytes sent since take_sent_bytes() last looked
  };

  std::vector<WriterReport> flush_locked();
  void take_incoming();
  std::size_t send_waiting(Connection& c, WriterReport& report);  // returns the bytes sent
  std::size_t trim(Connection& c);
  void run_worker();

  std::size_t max_backlog_bytes_;
  std::size_t max_backlog_batches_;
  mutable std::mutex state_mutex_;  ///< connections_, to_flush_: held for a whole flush
  std::unordered_map<int, Connection> connections_;
  int next_id_ = 1;
  std::vector<int> to_flush_;  ///< ids with queued batches or a backlog, in queue order
  std::mutex incoming_mutex_;  ///< incoming_: held only to append or swap
  std::vector<std::pair<int, std::string>> incoming_;
  std::unordered_map<int, std::size_t> incoming_at_;  ///< id -> its batch growing in incoming_
  std::mutex worker_mutex_;  ///< the fields below
  std::condition_variable worker_wake_;
  std::condition_variable worker_idle_;
  std::size_t requested_ = 0;
  bool stopping_ = false;
  std::vector<WriterReport> reports_;
  std::thread worker_;
};

}  // namespace evc
