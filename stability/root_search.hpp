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

// The `count` zeros inside the rectangle (multiple zeros repeated), located by
// subdivision down to rectangles of size min_size and Newton polishing.
// Throws std::runtime_error if the subdivision's counts do not add up or Newton
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

}  // namespace slipstrip
