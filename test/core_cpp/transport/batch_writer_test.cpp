// BatchWriter, the faces' send path, tested in C++ on real socket pairs (no Python, no ROS):
// byte-identical streams in order, a stalled reader that never blocks the writer and loses only
// whole batches, backlogs bounded in bytes and in batches, failures reported, slices of one
// buffer, the writer's own thread.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "epuck_vrep_compat/transport/batch_writer.hpp"

namespace {

using evc::BatchWriter;
using evc::WriterReport;

/// A connected stream socket pair with small buffers, so that a reader that stops fills them
/// soon; the reader side is non-blocking.
class SocketPair : public ::testing::Test {
 protected:
  void SetUp() override {
    int fds[2];
    ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, fds), 0) << std::strerror(errno);
    writer_fd = fds[0];
    reader_fd = fds[1];
    const int size = 16384;
    ::setsockopt(writer_fd, SOL_SOCKET, SO_SNDBUF, &size, sizeof size);
    ::setsockopt(reader_fd, SOL_SOCKET, SO_RCVBUF, &size, sizeof size);
    ::fcntl(reader_fd, F_SETFL, ::fcntl(reader_fd, F_GETFL) | O_NONBLOCK);
  }
  void TearDown() override {
    if (writer_fd >= 0) ::close(writer_fd);
    if (reader_fd >= 0) ::close(reader_fd);
  }
  /// Everything the reader can take now.
  std::string read_all() const {
    std::string out;
    char buffer[65536];
    while (true) {
      const ssize_t got = ::recv(reader_fd, buffer, sizeof buffer, 0);
      if (got <= 0) return out;
      out.append(buffer, static_cast<std::size_t>(got));
    }
  }
  int writer_fd = -1;
  int reader_fd = -1;
};

/// One framed message as TCPROS has it: a 4-byte little-endian length, then the body, whose
/// first 4 bytes are a sequence number.
std::string frame(std::uint32_t seq, std::size_t body_size) {
  std::string body(body_size, '\0');
  std::memcpy(&body[0], &seq, sizeof seq);
  const auto length = static_cast<std::uint32_t>(body.size());
  return std::string(reinterpret_cast<const char*>(&length), sizeof length) + body;
}

/// The sequence numbers of a stream of frames; fails the test on a partial frame.
std::vector<std::uint32_t> sequence_numbers(const std::string& stream) {
  std::vector<std::uint32_t> out;
  std::size_t at = 0;
  while (at < stream.size()) {
    std::uint32_t length = 0;
    std::uint32_t seq = 0;
    EXPECT_LE(at + 8, stream.size()) << "a partial frame header";
    if (at + 8 > stream.size()) break;
    std::memcpy(&length, stream.data() + at, 4);
    std::memcpy(&seq, stream.data() + at + 4, 4);
    EXPECT_LE(at + 4 + length, stream.size()) << "a partial message in the stream";
    out.push_back(seq);
    at += 4 + length;
  }
  return out;
}

std::size_t dropped_in(const std::vector<WriterReport>& reports, int id) {
  std::size_t dropped = 0;
  for (const WriterReport& r : reports) {
    EXPECT_EQ(r.id, id);
    EXPECT_FALSE(r.failed);
    dropped += r.dropped_batches;
  }
  return dropped;
}

TEST_F(SocketPair, AReaderThatKeepsUpGetsTheSameBytesInOrder) {
  BatchWriter writer(1 << 20);
  const int id = writer.open(writer_fd);
  std::string sent, received;
  for (std::uint32_t seq = 0; seq < 300; ++seq) {
    const std::string data = frame(seq, 50 + seq % 200);
    writer.queue(id, data.data(), data.size());
    sent += data;
    EXPECT_TRUE(writer.flush().empty());
    const auto counted = writer.take_sent_bytes(true);
    ASSERT_EQ(counted.size(), 1u);
    EXPECT_EQ(counted[0].id, id);
    EXPECT_EQ(counted[0].bytes, data.size());
    received += read_all();
  }
  EXPECT_EQ(received, sent);
  EXPECT_EQ(writer.backlog_bytes(), 0u);
}

TEST_F(SocketPair, AStalledReaderNeverBlocksAndLosesOnlyWholeBatches) {
  const std::size_t cap = 100000, body = 10000;
  BatchWriter writer(cap);
  const int id = writer.open(writer_fd);
  std::size_t dropped = 0;
  for (std::uint32_t seq = 0; seq < 500; ++seq) {  // 5 MB; the reader takes nothing
    const std::string data = frame(seq, body);
    writer.queue(id, data.data(), data.size());
    dropped += dropped_in(writer.flush(), id);  // a blocking write would never return
    EXPECT_LE(writer.backlog_bytes(), cap + body + 4);
  }
  EXPECT_GT(dropped, 0u);
  std::string stream = read_all();
  for (int k = 0; k < 200 && writer.backlog_bytes() > 0; ++k) {  // the reader is back
    dropped += dropped_in(writer.flush(), id);
    stream += read_all();
  }
  stream += read_all();
  EXPECT_EQ(writer.backlog_bytes(), 0u);
  const auto received = sequence_numbers(stream);
  ASSERT_FALSE(received.empty());
  EXPECT_TRUE(std::is_sorted(received.begin(), received.end()));
  EXPECT_EQ(received.front(), 0u);
  EXPECT_EQ(received.back(), 499u);
  EXPECT_EQ(received.size() + dropped, 500u);
}

TEST_F(SocketPair, TheBatchLimitAloneBoundsABacklogOfSmallBatches) {
  const std::size_t limit = 8, body = 200;
  BatchWriter writer(std::size_t{1} << 30, limit);
  EXPECT_EQ(writer.max_backlog_batches(), limit);
  const int id = writer.open(writer_fd);
  std::uint32_t queued = 0;
  std::size_t dropped = 0;
  while (writer.backlog_bytes() == 0) {  // until the socket is full
    const std::string data = frame(queued++, body);
    writer.queue(id, data.data(), data.size());
    dropped += dropped_in(writer.flush(), id);
  }
  for (int k = 0; k < 200; ++k) {
    const std::string data = frame(queued++, body);
    writer.queue(id, data.data(), data.size());
    dropped += dropped_in(writer.flush(), id);
    EXPECT_LE(writer.backlog_bytes(), limit * (body + 4));
  }
  EXPECT_GE(dropped, 200 - limit);
  std::string stream = read_all();
  for (int k = 0; k < 200 && writer.backlog_bytes() > 0; ++k) {
    writer.flush();
    stream += read_all();
  }
  stream += read_all();
  const auto received = sequence_numbers(stream);
  EXPECT_EQ(received.size() + dropped, queued);
  ASSERT_GE(received.size(), limit);
  for (std::size_t k = 1; k < limit; ++k) {  // the newest limit - 1 batches, behind the head
    EXPECT_EQ(received[received.size() - k], queued - k);
  }
  EXPECT_THROW(BatchWriter(1 << 20, 0), std::invalid_argument);
}

TEST_F(SocketPair, AClosedReaderIsReportedFailedAndItsBacklogGoes) {
  BatchWriter writer(1 << 20);
  const int id = writer.open(writer_fd);
  ::close(reader_fd);
  reader_fd = -1;
  const std::string data = frame(7, 100);
  writer.queue(id, data.data(), data.size());
  const auto reports = writer.flush();
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].id, id);
  EXPECT_TRUE(reports[0].failed);
  EXPECT_EQ(writer.backlog_bytes(), 0u);
  writer.close(id);
  EXPECT_EQ(writer.connection_count(), 0u);
  writer.queue(id, data.data(), data.size());  // a closed id's batches are dropped
  EXPECT_TRUE(writer.flush().empty());
}

TEST_F(SocketPair, SlicesOfOneBufferGrowOneBatchPerConnectionInCallOrder) {
  BatchWriter writer(1 << 20);
  const int a = writer.open(writer_fd);
  const int b = writer.open(writer_fd);  // a second duplicate of the same socket
  const std::string buffer = frame(1, 10) + frame(2, 20) + frame(3, 30);
  const std::vector<BatchWriter::Slice> slices = {
      {a, 0, 14}, {b, 14, 38}, {a, 38, buffer.size()}};
  writer.queue_slices(buffer.data(), buffer.size(), slices.data(), slices.size());
  EXPECT_TRUE(writer.flush().empty());
  EXPECT_EQ(read_all(), buffer.substr(0, 14) + buffer.substr(38) + buffer.substr(14, 24));
  const std::vector<BatchWriter::Slice> outside = {{a, 0, 14}, {a, 10, buffer.size() + 1}};
  EXPECT_THROW(writer.queue_slices(buffer.data(), buffer.size(), outside.data(), outside.size()),
               std::out_of_range);
  EXPECT_TRUE(writer.flush().empty());
  EXPECT_EQ(read_all(), "");  // nothing of the refused call was queued
}

TEST_F(SocketPair, TheWritersThreadSendsWhatFlushWould) {
  BatchWriter writer(1 << 20);
  const int id = writer.open(writer_fd);
  std::string sent, received;
  for (std::uint32_t seq = 0; seq < 200; ++seq) {
    const std::string data = frame(seq, 64);
    writer.queue(id, data.data(), data.size());
    sent += data;
    writer.request_flush();
    if (seq % 10 == 9) {
      EXPECT_TRUE(writer.take_reports(true).empty());
      received += read_all();
    }
  }
  EXPECT_TRUE(writer.take_reports(true).empty());
  received += read_all();
  EXPECT_EQ(received, sent);
}

TEST(BatchWriterDescriptors, ANegativeOrClosedDescriptorIsRefusedWithEbadf) {
  BatchWriter writer(1 << 20);
  for (bool own : {true, false}) {
    try {
      writer.open(-1, own);
      ADD_FAILURE() << "a negative descriptor was accepted (own " << own << ")";
    } catch (const std::system_error& e) {
      EXPECT_EQ(e.code().value(), EBADF);
    }
  }
  EXPECT_EQ(writer.connection_count(), 0u);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
