#include "epuck_vrep_compat/sensors/blob_detection.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace evc {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A horizontal run of object pixels on V-REP row y (bottom-up), columns first..last.
struct Run {
  int y, first, last;
};

struct Point {
  std::int64_t x, y;
};

// Runs of object pixels, V-REP's scan order: bottom row first, left to right; row_start[y] is
// the first run of row y, row_start[height] the run count.
void find_runs(const std::uint8_t* pixels, int height, int width, int channels,
               double threshold, std::vector<Run>& runs, std::vector<std::size_t>& row_start) {
  const double intensity_sum_min = 3.0 * 255.0 * threshold;
  runs.clear();
  row_start.assign(static_cast<std::size_t>(height) + 1, 0);
  for (int y = 0; y < height; ++y) {
    row_start[y] = runs.size();
    const std::uint8_t* row =
        pixels + static_cast<std::size_t>(height - 1 - y) * width * channels;
    int first = -1;
    for (int x = 0; x <= width; ++x) {
      bool object = false;
      if (x < width) {
        const std::uint8_t* p = row + static_cast<std::size_t>(x) * channels;
        object = channels == 1 ? p[0] != 0 : double(p[0]) + p[1] + p[2] >= intensity_sum_min;
      }
      if (object && first < 0) first = x;
      if (!object && first >= 0) {
        runs.push_back(Run{y, first, x - 1});
        first = -1;
      }
    }
  }
  row_start[height] = runs.size();
}

std::size_t find_root(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

// Blob index per run, blobs numbered in scan order: runs touching (8-connectivity) in
// neighbouring rows are joined under the earliest run.
std::vector<std::size_t> label_runs(const std::vector<Run>& runs,
                                    const std::vector<std::size_t>& row_start,
                                    std::size_t& blob_count) {
  std::vector<std::size_t> parent(runs.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t y = 1; y + 1 < row_start.size(); ++y) {
    std::size_t below = row_start[y - 1];
    for (std::size_t i = row_start[y]; i < row_start[y + 1]; ++i) {
      while (below < row_start[y] && runs[below].last + 1 < runs[i].first) ++below;
      for (std::size_t j = below; j < row_start[y] && runs[j].first <= runs[i].last + 1; ++j) {
        const std::size_t a = find_root(parent, i), b = find_root(parent, j);
        parent[std::max(a, b)] = std::min(a, b);
      }
    }
  }
  std::vector<std::size_t> blob(runs.size());
  blob_count = 0;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::size_t root = find_root(parent, i);
    blob[i] = root == i ? blob_count++ : blob[root];
  }
  return blob;
}

std::int64_t cross(const Point& o, const Point& a, const Point& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Convex hull (Andrew's monotone chain), exact in integers; a point or a segment stays as is.
std::vector<Point> convex_hull(std::vector<Point> points) {
  std::sort(points.begin(), points.end(),
            [](const Point& a, const Point& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  if (points.size() < 3) return points;
  std::vector<Point> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

// The bounding box of the points turned by angle a, as V-REP computes it.
struct TurnedBox {
  double angle = 0.0;
  double area = std::numeric_limits<double>::infinity();
  double min_x = 0.0, max_x = 0.0, min_y = 0.0, max_y = 0.0;
};

TurnedBox turned_box(const std::vector<Point>& hull, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  TurnedBox box{angle, 0.0, std::numeric_limits<double>::infinity(),
                -std::numeric_limits<double>::infinity(),
                std::numeric_limits<double>::infinity(),
                -std::numeric_limits<double>::infinity()};
  for (const Point& p : hull) {
    const double x = double(p.x) * c - double(p.y) * s;
    const double y = double(p.x) * s + double(p.y) * c;
    box.min_x = std::min(box.min_x, x);
    box.max_x = std::max(box.max_x, x);
    box.min_y = std::min(box.min_y, y);
    box.max_y = std::max(box.max_y, y);
  }
  box.area = (box.max_x - box.min_x) * (box.max_y - box.min_y);
  return box;
}

// V-REP's coarse-to-fine search for the rotation of least box area.
TurnedBox smallest_turned_box(const std::vector<Point>& hull) {
  TurnedBox best;
  const auto consider = [&](double angle) {
    const TurnedBox box = turned_box(hull, angle);
    if (box.area < best.area) best = box;
  };
  double step = kPi / 8.0;
  for (int j = 0; j < 4; ++j) consider(step * j);
  for (int level = 0; level < 3; ++level) {
    step /= 3.0;
    const double centre = best.angle;
    for (int j = -2; j <= 2; ++j) {
      if (j != 0) consider(centre + step * j);
    }
  }
  return best;
}

Blob describe(const std::vector<Point>& hull, double pixel_count, int height, int width) {
  const TurnedBox box = smallest_turned_box(hull);
  const double a = box.angle;
  const double cx = 0.5 * (box.max_x + box.min_x), cy = 0.5 * (box.max_y + box.min_y);
  // The centre turned back by -a; +0.5 from pixel centres to pixel edges.
  const double x = cx * std::cos(-a) - cy * std::sin(-a) + 0.5;
  const double y = cx * std::sin(-a) + cy * std::cos(-a) + 0.5;
  return Blob{pixel_count / (double(width) * height), -a, x / width, y / height,
              (box.max_x - box.min_x) / width, (box.max_y - box.min_y) / height};
}

}  // namespace

std::vector<Blob> detect_blobs(const std::uint8_t* pixels, int height, int width, int channels,
                               double threshold, double min_size) {
  if (height < 1 || width < 1) throw std::invalid_argument("image must be at least 1 x 1");
  if (channels != 1 && channels != 3) {
    throw std::invalid_argument("image must have 1 channel (mask) or 3 (RGB)");
  }
  if (!std::isfinite(threshold)) throw std::invalid_argument("threshold must be finite");
  if (!std::isfinite(min_size)) throw std::invalid_argument("min_size must be finite");
  thread_local std::vector<Run> runs;
  thread_local std::vector<std::size_t> row_start;
  find_runs(pixels, height, width, channels, threshold, runs, row_start);
  std::size_t blob_count = 0;
  const std::vector<std::size_t> blob_of_run = label_runs(runs, row_start, blob_count);
  std::vector<double> pixel_count(blob_count, 0.0);
  std::vector<std::vector<Point>> ends(blob_count);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const Run& run = runs[i];
    const std::size_t b = blob_of_run[i];
    pixel_count[b] += run.last - run.first + 1;
    ends[b].push_back(Point{run.first, run.y});
    if (run.last != run.first) ends[b].push_back(Point{run.last, run.y});
  }
  std::vector<std::size_t> order;
  const double area = double(width) * height;
  for (std::size_t b = 0; b < blob_count; ++b) {
    if (pixel_count[b] / area >= min_size) order.push_back(b);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return pixel_count[a] > pixel_count[b];
  });
  std::vector<Blob> blobs;
  blobs.reserve(order.size());
  for (const std::size_t b : order) {
    blobs.push_back(describe(convex_hull(std::move(ends[b])), pixel_count[b], height, width));
  }
  return blobs;
}

std::vector<float> blob_packet(const std::vector<Blob>& blobs) {
  std::vector<float> packet{static_cast<float>(blobs.size()), float(kBlobValues)};
  packet.reserve(2 + kBlobValues * blobs.size());
  for (const Blob& blob : blobs) {
    for (const double value : {blob.size, blob.orientation_rad, blob.x, blob.y, blob.width,
                               blob.height}) {
      packet.push_back(static_cast<float>(value));
    }
  }
  return packet;
}

}  // namespace evc
