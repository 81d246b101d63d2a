#pragma once
// Zeros of an analytic function in a rectangle of the complex plane: the
// argument principle on rectangles (recursive subdivision until each holds one
// zero) and Newton polishing, for the stability of any pair of bodies
// (stability/interface_stability.*).  The same algorithm as the identical-strip
// search in stability/linear_stability.cpp, which keeps its own copy: moving it
// onto this one changes the rounding (inlining, FMA contraction) and reorders a
// conjugate pair in an existing test that compares two root lists by index.  The function must have no poles inside
// the rectangle (callers remove them analytically or keep them outside), so
// that the winding number counts zeros only.
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

// All zeros inside the rectangle, located down to 1e-9 of its larger side and
// sorted by decreasing real part (the fastest-growing first), then by
// decreasing imaginary part.
std::vector<std::complex<double>> sorted_zeros_in(const AnalyticFunction& g, const Rectangle& box);

}  // namespace slipstrip
