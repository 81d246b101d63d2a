#pragma once
// Zeros of an analytic function in a rectangle of the complex plane: the
// argument principle on rectangles (recursive subdivision until each holds one
// zero) and Newton polishing, for the stability of any pair of bodies
// (stability/linear_stability.*, stability/interface_stability.*,
// stability/oblique_stability.*).  The function must have no poles inside the
// rectangle (callers remove them analytically or keep them outside), so that
// the winding number counts zeros only.
#include <complex>
#include <functional>
#include <vector>

namespace slipstrip {

using AnalyticFunction = std::function<std::complex<double>(std::complex<double>)>;

// Rectangle re0 <= Re z <= re1, im0 <= Im z <= im1.
struct Rectangle {
  double re0, re1, im0, im1;
};

// Winding number of g around the rectangle's boundary, i.e. its number of zeros
// inside.  Each edge is sampled at 256 points and refined until each step turns
// the argument by less than pi/4.  Throws std::runtime_error if g is not finite
// or zero on the contour, or the count is not resolved to an integer.
int count_zeros(const AnalyticFunction& g, const Rectangle& box);
// The same with `samples_per_edge` initial samples per edge instead of 256.
int count_zeros(const AnalyticFunction& g, const Rectangle& box, int samples_per_edge);

// The `count` zeros inside the rectangle (multiple zeros repeated), located by
// subdivision down to rectangles of size min_size and Newton polishing.
// Where the counts of a split do not add up, the three contours are recounted
// at 16 and 256 times the sampling.  Throws std::runtime_error if the counts
// still do not add up or Newton
// fails in a rectangle smaller than min_size.
std::vector<std::complex<double>> locate_zeros(const AnalyticFunction& g, const Rectangle& box,
                                               int count, double min_size);

// The size down to which the searches below locate zeros: 1e-9 of the
// rectangle's larger side.
double location_resolution(const Rectangle& box);

// Orders roots the fastest-growing first: by decreasing real part, and roots
// whose real parts differ by at most `tie` by decreasing imaginary part.  The
// tie makes the order of a complex-conjugate pair (equal real parts, which
// Newton returns equal only to rounding) the same in every build: +i first.
// Runs of roots whose successive real parts lie within `tie` count as ties.
void sort_fastest_first(std::vector<std::complex<double>>& roots, double tie);

// All zeros inside the rectangle, located down to location_resolution(box) and
// ordered by sort_fastest_first with that resolution as the tie.
std::vector<std::complex<double>> sorted_zeros_in(const AnalyticFunction& g, const Rectangle& box);

// Rectangles tiling `box` (Re z >= 0 near the imaginary axis) whose sizes grow
// with the distance from the origin: the square Re z <= inner, |Im z| <= inner
// (clipped to the box), then the rings between the squares of half-sides
// s = inner 4^j and 4 s, each cut into a top, a bottom and a right rectangle.
// Why: a dispersion relation whose rate-and-state zeros and poles cluster within
// |z| <= inner/2 while the box is set by a much larger scale (elastic waves).
// One contour of the whole box, 256 samples per edge, steps over that cluster
// and can miss a full turn of the argument; here every edge of ring j lies at
// |z| >= s and is sampled every <= 4 s / 256 = s / 64, so each zero or pole of
// the cluster (distance >= s/2) turns the argument by <= 2 atan(1/64) ~ 0.03
// rad per step and no sum of a few can hide a turn between two samples.  The
// inner square is sampled every inner/128: the cluster's own scale, as the
// rate-and-state box of identical bodies is.  One rectangle (the box itself)
// when inner covers the box.
std::vector<Rectangle> graded_tiling(const Rectangle& box, double inner);

// The zeros in `box` counted and located piece by piece over
// graded_tiling(box, inner), located down to location_resolution(box) and ordered
// as sorted_zeros_in.  count_zeros_graded is the count alone.  Each piece's
// count is taken once it stops changing when its contour's sampling is made 4
// times denser (from 256 up to 65536 samples per edge; throws if it has not
// settled by then): a zero with a small Re next to a pole on Re = 0 (lossless
// strips) can turn the argument by 2 pi within one coarse step.
int count_zeros_graded(const AnalyticFunction& g, const Rectangle& box, double inner);
std::vector<std::complex<double>> sorted_zeros_graded(const AnalyticFunction& g, const Rectangle& box,
                                                      double inner);

}  // namespace slipstrip
