// subscribe_all: one process that subscribes to every advertised topic matching a regex and
// counts what arrives, so a benchmark can load a simulator with a realistic consumer.
//
// It uses topic_tools::ShapeShifter, so it needs no message types and never deserialises a
// message: a callback costs one buffer copy (done by roscpp) and two additions. All callbacks
// and the once-a-second master re-scan run on the main thread, so the counters need no locks.
//
// Usage: subscribe_all [--regex R] [--duration S] [--scan-period S] [--queue-size Q]
//                      [--per-topic] [--progress S] [ROS remappings]
// On SIGINT/SIGTERM, or after --duration seconds, it prints one JSON line to stdout:
//   {"topics":n,"messages":m,"bytes":b,"wall_s":t,"rate_hz_total":m/t}
// "bytes" counts serialised message bodies, without TCPROS's 4-byte length prefix.
// "wall_s" runs from the first master scan to the end. SIGUSR1 zeroes the counters and restarts
// that clock, so a benchmark can count over an exact window once every subscription is
// connected. Diagnostics go to stderr only; with --progress S, every S seconds one JSON line
//   {"progress_s":t,"topics":n,"publishers":p,"delivered":d,"messages":m}
// (topics with a publisher connection, topics that have delivered a message since the start,
// whatever SIGUSR1 reset, and messages received since the start or the last SIGUSR1), so a
// benchmark can tell when every subscription delivers, and count what arrives as it goes.

#include <ros/callback_queue.h>
#include <ros/master.h>
#include <ros/ros.h>
#include <topic_tools/shape_shifter.h>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <regex>
#include <string>
#include <vector>

namespace {

volatile std::sig_atomic_t g_stop_requested = 0;

volatile std::sig_atomic_t g_reset_requested = 0;

void requestStop(int /*signal*/) { g_stop_requested = 1; }
void requestReset(int /*signal*/) { g_reset_requested = 1; }

struct Options {
  std::string regex = "^(?!/rosout).*";  // everything except /rosout and /rosout_agg
  double duration_s = 0.0;               // 0: run until SIGINT/SIGTERM
  double scan_period_s = 1.0;
  // Deep enough to absorb a burst of one robot's step while the main thread serves others;
  // a dropped message would hide a slow consumer, so keep it generous.
  int queue_size = 1000;
  bool per_topic = false;
  double progress_s = 0.0;  // 0: no progress lines
};

struct TopicCount {
  ros::Subscriber subscriber;
  std::uint64_t messages = 0;
  std::uint64_t bytes = 0;
  bool delivered = false;  // a message arrived since the start (SIGUSR1 leaves it)
};

void printUsageAndExit(const char* program) {
  std::fprintf(stderr,
               "usage: %s [--regex R] [--duration S] [--scan-period S] [--queue-size Q] "
               "[--per-topic] [--progress S]\n",
               program);
  std::exit(2);
}

double parsePositive(const char* name, const char* text) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || value < 0.0) {
    std::fprintf(stderr, "subscribe_all: %s must be a non-negative number, got '%s'\n", name,
                 text);
    std::exit(2);
  }
  return value;
}

Options parseOptions(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--regex" && has_value) {
      options.regex = argv[++i];
    } else if (arg == "--progress" && has_value) {
      options.progress_s = parsePositive("--progress", argv[++i]);
    } else if (arg == "--duration" && has_value) {
      options.duration_s = parsePositive("--duration", argv[++i]);
    } else if (arg == "--scan-period" && has_value) {
      options.scan_period_s = parsePositive("--scan-period", argv[++i]);
    } else if (arg == "--queue-size" && has_value) {
      options.queue_size = static_cast<int>(parsePositive("--queue-size", argv[++i]));
    } else if (arg == "--per-topic") {
      options.per_topic = true;
    } else {
      printUsageAndExit(argv[0]);
    }
  }
  if (options.scan_period_s <= 0.0 || options.queue_size < 1) {
    std::fprintf(stderr, "subscribe_all: --scan-period and --queue-size must be positive\n");
    std::exit(2);
  }
  return options;
}

/// Subscribes to the matching topics the master knows and this process does not yet follow.
class TopicCounter {
 public:
  TopicCounter(ros::NodeHandle& node, const Options& options)
      : node_(node), pattern_(options.regex), queue_size_(options.queue_size) {}

  void scanMaster() {
    ros::master::V_TopicInfo topics;
    if (!ros::master::getTopics(topics)) {
      ROS_WARN_THROTTLE(10.0, "subscribe_all: master scan failed, retrying");
      return;
    }
    for (const ros::master::TopicInfo& topic : topics) {
      if (counts_.count(topic.name) != 0 || !std::regex_match(topic.name, pattern_)) continue;
      TopicCount& count = counts_[topic.name];
      count.subscriber = node_.subscribe<topic_tools::ShapeShifter>(
          topic.name, queue_size_,
          [&count](const topic_tools::ShapeShifter::ConstPtr& message) {
            ++count.messages;
            count.bytes += message->size();
            count.delivered = true;
          });
    }
  }

  void reset() {
    for (auto& entry : counts_) {
      entry.second.messages = 0;
      entry.second.bytes = 0;
    }
  }

  void printProgress(double seconds) const {
    std::size_t publishers = 0;
    std::size_t delivered = 0;
    std::uint64_t messages = 0;
    for (const auto& entry : counts_) {
      if (entry.second.subscriber.getNumPublishers() > 0) ++publishers;
      if (entry.second.delivered) ++delivered;
      messages += entry.second.messages;
    }
    std::fprintf(stderr, "{\"progress_s\":%.1f,\"topics\":%zu,\"publishers\":%zu,"
                 "\"delivered\":%zu,\"messages\":%llu}\n", seconds, counts_.size(), publishers,
                 delivered, static_cast<unsigned long long>(messages));
    std::fflush(stderr);
  }

  void printJson(double wall_s, bool per_topic) const {
    std::uint64_t messages = 0;
    std::uint64_t bytes = 0;
    for (const auto& entry : counts_) {
      messages += entry.second.messages;
      bytes += entry.second.bytes;
    }
    std::printf("{\"topics\":%zu,\"messages\":%llu,\"bytes\":%llu,\"wall_s\":%.6f,"
                "\"rate_hz_total\":%.3f",
                counts_.size(), static_cast<unsigned long long>(messages),
                static_cast<unsigned long long>(bytes), wall_s,
                wall_s > 0.0 ? messages / wall_s : 0.0);
    if (per_topic) {
      // ROS graph names are [A-Za-z0-9_/~], so they need no JSON escaping.
      std::printf(",\"per_topic\":{");
      const char* separator = "";
      for (const auto& entry : counts_) {
        std::printf("%s\"%s\":{\"messages\":%llu,\"bytes\":%llu}", separator, entry.first.c_str(),
                    static_cast<unsigned long long>(entry.second.messages),
                    static_cast<unsigned long long>(entry.second.bytes));
        separator = ",";
      }
      std::printf("}");
    }
    std::printf("}\n");
    std::fflush(stdout);
  }

 private:
  ros::NodeHandle& node_;
  const std::regex pattern_;
  const int queue_size_;
  // std::map never moves its elements, so callbacks may hold references to them.
  std::map<std::string, TopicCount> counts_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "subscribe_all",
            ros::init_options::AnonymousName | ros::init_options::NoSigintHandler);
  const Options options = parseOptions(argc, argv);  // ros::init removed the remappings
  std::signal(SIGINT, requestStop);
  std::signal(SIGTERM, requestStop);
  std::signal(SIGUSR1, requestReset);
  if (!ros::master::check()) {
    std::fprintf(stderr, "subscribe_all: no ROS master at %s\n", ros::master::getURI().c_str());
    return 1;
  }

  ros::NodeHandle node;
  TopicCounter counter(node, options);
  using Clock = std::chrono::steady_clock;
  Clock::time_point start = Clock::now();
  Clock::time_point next_scan = start;
  const Clock::time_point first_scan = start;
  const auto progress_period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(options.progress_s));
  Clock::time_point next_progress = start + progress_period;
  const auto seconds_since_start = [&start] {
    return std::chrono::duration<double>(Clock::now() - start).count();
  };
  const auto scan_period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(options.scan_period_s));

  ros::CallbackQueue& queue = *ros::getGlobalCallbackQueue();
  while (!g_stop_requested && ros::ok()) {
    if (g_reset_requested) {
      g_reset_requested = 0;
      counter.reset();
      start = Clock::now();
    }
    if (Clock::now() >= next_scan) {
      counter.scanMaster();
      next_scan += scan_period;
    }
    if (options.progress_s > 0.0 && Clock::now() >= next_progress) {
      counter.printProgress(std::chrono::duration<double>(Clock::now() - first_scan).count());
      next_progress += progress_period;
    }
    if (options.duration_s > 0.0 && seconds_since_start() >= options.duration_s) break;
    queue.callAvailable(ros::WallDuration(0.01));
  }
  const double wall_s = seconds_since_start();
  counter.printJson(wall_s, options.per_topic);
  ros::shutdown();
  return 0;
}
