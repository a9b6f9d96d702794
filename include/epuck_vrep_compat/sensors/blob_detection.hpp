/// @file
/// V-REP's "blob detection on work image" filter (simVision.blobDetectionOnWorkImg; the
/// vision sensor filter of V-REP 3.x), for the cell's blob-tracking cameras (models.md §7).
///
/// Read from the CoppeliaRobotics/simVision source, which defines the values; our image rows
/// run top-down (row 0 at the top, as the renderer produces), V-REP's bottom-up, so below a
/// pixel at (row, col) sits at x = col, y = H - 1 - row (pixel centres, y up).
///
///  - Object pixels: nonzero, for a one-channel mask; (r + g + b) / (3 · 255) >= threshold for
///    an RGB image (V-REP's rule on its work image).
///  - Blobs: 8-connected components. size = pixels / (W H); blobs with size < min_size are
///    dropped.
///  - Rectangle: V-REP searches the rotation a of the pixel centres that minimises the area of
///    their axis-aligned bounding box: a = 0, π/8, 2π/8, 3π/8, then three times around the best
///    so far at ±1, ±2 steps of a third of the previous step (first strict minimum wins). The
///    box is the blob's bounding rectangle turned by -a.
///  - Values per blob, V-REP's order:
///        size         pixels / (W H)
///        orientation  -a (rad, counter-clockwise with y up): the rectangle's first side from
///                     +x; a rectangle has the same extent at θ and θ ± π/2, so read it modulo
///                     π/2. Values fall in about [-1.43, 0.35].
///        x, y         rectangle centre + half a pixel, over W and H: 0..1, x from the left, y
///                     from the BOTTOM (0.5, 0.5 = image centre)
///        width        rectangle extent along the first side / W
///        height       rectangle extent along the second side / H
///    Extents are between pixel centres, as in V-REP: a blob n pixels wide reads (n - 1) / W.
///
/// Deviation from V-REP: blobs come largest first (ties in V-REP's scan order: bottom row
/// first, left to right), where V-REP lists them in the order its labelling merged them.
///
/// Cost: run-length labelling with union-find, then per blob the convex hull of its runs' end
/// pixels (the box of a point set is the box of its hull, so the values equal V-REP's search
/// over all boundary pixels, bit for bit) and the 16 rotations on the hull only.
#pragma once

#include <cstdint>
#include <vector>

namespace evc {

/// One blob, V-REP's values (see the file comment).
struct Blob {
  double size = 0.0;
  double orientation_rad = 0.0;
  double x = 0.0;
  double y = 0.0;
  double width = 0.0;
  double height = 0.0;
};

/// Values per blob in V-REP's packet.
constexpr int kBlobValues = 6;

/// Blobs of an image of height × width pixels, row-major from the top row, @p channels = 1
/// (mask) or 3 (RGB), largest first. Throws std::invalid_argument for sizes < 1, other
/// channel counts, threshold or min_size not finite.
std::vector<Blob> detect_blobs(const std::uint8_t* pixels, int height, int width, int channels,
                               double threshold = 0.5, double min_size = 0.0);

/// V-REP's packet: {count, 6, then per blob size, orientation, x, y, width, height}.
std::vector<float> blob_packet(const std::vector<Blob>& blobs);

}  // namespace evc
