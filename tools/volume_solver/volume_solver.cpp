// slipstrip_volume: an independent 2D elastodynamic volume solver for the
// strip-pair problem, used only as a test oracle for the boundary-integral
// solver (docs/benchmarks/volume_solver.md).  It shares NOTHING with
// slipstrip's kernels (no strip response, no history operator, no FFT): the
// bulk is a staggered-grid velocity-stress finite-difference scheme
// (Virieux 1986), second order in space and time.  Only the friction law
// (strength, state evolution, local solve; the batch forms of
// friction/batch_solve.hpp, which are the scalar routines vectorised over
// nodes) is taken from friction/, because the friction law is not what is
// being tested.
//
// Problem (perturbation about steady sliding at v0; docs/theory.md section 1):
// by the mirror symmetry of the two identical strips, one strip 0 < y < H,
// periodic in x with period L, with
//   y = H : u_x = 0, sigma_yy = 0        (an exact mirror plane of the grid)
//   y = 0 : u_x = slip'/2, sigma_yy = 0, sigma_xy = tau - tau_ref
// where slip' = slip - v0 t, tau = F(v, phi) is the frictional strength at
// slip rate v = v0 + 2 du_x/dt, and tau_ref = F(v0, phi_ss(v0)).  An optional
// imposed shear-load pulse P(x, t) adds to the load: tau = tau_ref + P + sigma_xy.
//
// Grid (spacing h in x and y, nx = L/h, ny = H/h, both integers):
//   v_x   at (i h, j h)            j = 0..ny   (row 0: the interface; row ny: 0)
//   v_y   at ((i+1/2) h, (j+1/2) h) j = 0..ny-1
//   s_xx, s_yy at ((i+1/2) h, j h) j = 0..ny   (s_yy = 0 on rows 0 and ny)
//   s_xy  at (i h, (j+1/2) h)      j = 0..ny-1
// Time: stresses, state and slip at t_n = n dt; velocities at t_{n+1/2}.
// Interface node (traction at split nodes, Andrews 1999; Day et al. 2005):
// half a cell of mass,
//   rho (h/2) dv_x/dt = (h/2) d s_xx/dx + s_xy(h/2) - T,   T = tau - tau_ref - P.
// The friction law is imposed at t_n on the slip rate V^n = v0 + v_x^{n-1/2} + v_x^{n+1/2}
// (the time-centred value), which turns the update into the scalar equation
//   tau_h - eta_h V = F(V, phi^n),  eta_h = rho h / (2 dt),
//   tau_h = tau_ref + P + (h/2) d s_xx/dx + s_xy(h/2) + eta_h (v0 + 2 v_x^{n-1/2}),
// solved by slipstrip::solve_slip_rate (in its batch form).  The state then advances with the
// exact constant-rate update over [t_n, t_{n+1}] at V^{n+1/2} = v0 + 2 v_x^{n+1/2}
// (midpoint rule: second order).  On row 0, s_yy = 0 gives
// d s_xx/dt = 4 mu (lambda + mu)/(lambda + 2 mu) d v_x/dx.
//
// Two bodies (bottom=elastic|rigid, or plane=antiplane; docs/benchmarks/volume_bodies.md):
// a top body 0 < y < H and a bottom body -H_b < y < 0 with their own materials,
// each on the same staggered grid in its own frame (the bottom body reflected,
// y' = -y: v_y' = -v_y, s_xy' = -s_xy, the same equations and row sweeps),
// joined at y = 0 by split nodes: v_x (v_z) on each side, one shear traction T,
//   rho_t (h/2) dv_t/dt = A_t - T,  rho_b (h/2) dv_b/dt = A_b + T,
//   A = (h/2) d s_xx/dx + s_xy(h/2)   (each in its own frame),
// slip rate V = v0 + v_t - v_b, and the same time-centred friction solve with
//   eta_h = h / (dt (1/rho_t + 1/rho_b)),  tau_h = tau_ref + P + eta_h V_free,
//   V_free = v0 + v_t^{n-1/2} - v_b^{n-1/2} + (dt/h)(A_t/rho_t - A_b/rho_b).
// In-plane, v_y is continuous (no opening) and the interface row carries one
// normal stress s_yy with a split s_xx: each half cell has its own normal
// strain e_t, e_b with (e_t + e_b)/2 = (v_y,t(h/2) + v_y,b(h/2))/h (own frames)
// and s_yy = lambda e_xx + M e (per side) the same on both sides, so
//   d s_yy/dt = [2 e_avg + (lambda_t/M_t) e_xx,t + (lambda_b/M_b) e_xx,b] / (1/M_t + 1/M_b).
// (For identical bodies this is s_yy = 0 and s_xx = Mb e_xx, the mirror scheme.)
// The normal stress sigma = sigma0 - s_yy (at the nodes: the mean of the two
// neighbouring cells) changes, and the friction sees the Prakash-Clifton
// effective normal stress, d sigma_eff/dt = -r (sigma_eff - sigma), r = (|V| + v*)/L_sigma
// or 1/t_sigma (as slipstrip, docs/bodies.md section 4), integrated exactly over
// a step for sigma linear in time at the mid-step rate from V^{n+1/2}.  A rigid
// bottom is the limit 1/rho_b = 1/M_b = 0 with v_b = 0.  Antiplane: v_z, s_xz,
// s_yz only (SH), sigma = sigma0.  Outer faces: v_x (v_z) = 0 and s_yy = 0
// (driven).  Each interface node is solved on its own (the scalar local solve).
//
// Performance (docs/benchmarks/volume_solver.md): each sweep runs over whole
// rows with the periodic wrap peeled off, so the inner loops are contiguous and
// vectorise; one OpenMP parallel region spans the time loop (rows and interface
// nodes split between threads, OMP_NUM_THREADS); nothing is allocated inside it.
// Every node's update is independent of the thread count, so the results are
// the same for any number of threads.
//
// Usage: slipstrip_volume key=value ...   (see usage() below)
// Output: a text file of station time series at t_n (every `output_every` steps),
// with final_profile=FILE the interface fields at the end, and with
// snapshot_file / timeseries_file binary records of the interface
// (tools/volume_solver/volume.py turns them into a slipstrip run file).
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "friction/batch_solve.hpp"
#include "friction/friction_law.hpp"

namespace {

constexpr double pi = 3.14159265358979323846;

void usage() {
  std::cerr <<
      "usage: slipstrip_volume key=value ...\n"
      "  geometry : length=L height=H nx=N (h = L/nx; H/h must be a whole number)\n"
      "  material : shear_modulus=mu poisson_ratio=nu density=rho plane=strain|stress|antiplane\n"
      "  bottom   : bottom=mirror|elastic|rigid (default mirror: the mirror image of the top body)\n"
      "             bottom_height= bottom_shear_modulus= bottom_poisson_ratio= bottom_density= (elastic)\n"
      "             normal_stress_slip=L_sigma (0: characteristic_slip) normal_stress_time=t_sigma (0: off)\n"
      "  loading  : driving_velocity=v0 normal_stress=sigma0\n"
      "  friction : law=paper|dieterich_ruina|regularized f0= a= b= characteristic_slip= v_star= phi_star=\n"
      "             state_law=aging|slip\n"
      "  pulse    : load_pulse_amplitude=P0 pulse_center=x0 pulse_width=w rise_time=T (sin^4 bump on [0,T])\n"
      "  initial  : local_amplitude= local_center= local_width= (Gaussian change of phi, relative)\n"
      "             initial_state=FILE (phi at the nx interface nodes, nx raw float64; replaces local_*)\n"
      "  time     : duration=t_end cfl=c (dt = c h / c_d, default 0.5; or dt=...) \n"
      "  output   : stations=x1,x2,... (on grid nodes) out=FILE output_every=k final_profile=FILE\n"
      "             (columns per station: slip, slip_rate, shear_stress, state, normal_stress,\n"
      "              effective_normal_stress)\n"
      "             snapshot_file=FILE snapshot_interval=s (records: t, slip[nx], slip_rate[nx],\n"
      "               state[nx], shear_stress[nx], raw float64, appended and flushed per snapshot)\n"
      "             timeseries_file=FILE timeseries_interval=s (records: t, max slip rate, mean slip,\n"
      "               mean shear stress, raw float64)\n"
      "             progress=s (seconds of wall time between progress lines on stderr; 0 = off)\n"
      "  interface: stick_hold=1|0 (hold V^{n+1/2} = 0 at stuck nodes; default 1)\n"
      "  restart  : checkpoint=FILE checkpoint_interval=s (wall seconds between checkpoints)\n"
      "             checkpoint_steps=k (every k steps) halt_after_steps=k (checkpoint at step k, exit 3)\n"
      "             resume=1 (continue from FILE: same arguments apart from these and progress;\n"
      "               the output files are cut back to what they held at the checkpoint)\n"
      "  threads  : OMP_NUM_THREADS (results do not depend on it)\n";
}

struct Args {
  std::map<std::string, std::string> kv;
  std::map<std::string, bool> used;
  double num(const std::string& k, double def, bool required = false) {
    auto it = kv.find(k);
    if (it == kv.end()) {
      if (required) throw std::invalid_argument("missing required argument " + k);
      return def;
    }
    used[k] = true;
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (end == it->second.c_str() || *end != '\0')
      throw std::invalid_argument(k + " = '" + it->second + "' is not a number");
    return v;
  }
  std::string str(const std::string& k, const std::string& def) {
    auto it = kv.find(k);
    if (it == kv.end()) return def;
    used[k] = true;
    return it->second;
  }
};

// Lame's lambda of a body: plane strain, plane stress (thin plate, sigma_zz = 0);
// antiplane (SH) does not use it.
double lame_lambda(double mu, double nu, const std::string& plane) {
  return plane == "stress" ? 2 * mu * nu / (1 - nu) : 2 * mu * nu / (1 - 2 * nu);
}

std::vector<double> parse_list(const std::string& s) {
  std::vector<double> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(std::stod(item));
  }
  return out;
}

// A C stdio file closed on scope exit (binary output written with fwrite).
struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

File open_file(const std::string& path, const char* mode) {
  File f(std::fopen(path.c_str(), mode));
  if (!f) throw std::runtime_error("cannot open " + path);
  return f;
}

// The step of the k-th sample at interval `every_s` seconds (0: never).
long sample_step(long k, double every_s, double dt) {
  return every_s > 0 ? std::lround(k * every_s / dt) : -1;
}

// --- row sweeps (periodic in x; the wrap is peeled so the inner loop is contiguous)
// v_x row j: rho dv_x/dt = d s_xx/dx + d s_xy/dy, s_xx at i+1/2 (index i), s_xy rows j, j-1.
inline void update_vx_row(double* __restrict v, const double* __restrict sxx,
                          const double* __restrict sxy_up, const double* __restrict sxy_dn, double c, int nx) {
  v[0] += c * (sxx[0] - sxx[nx - 1] + sxy_up[0] - sxy_dn[0]);
#pragma omp simd
  for (int i = 1; i < nx; ++i) v[i] += c * (sxx[i] - sxx[i - 1] + sxy_up[i] - sxy_dn[i]);
}

// v_y row j (at y = (j+1/2) h): rho dv_y/dt = d s_xy/dx + d s_yy/dy.
inline void update_vy_row(double* __restrict v, const double* __restrict sxy, const double* __restrict syy_dn,
                          const double* __restrict syy_up, double c, int nx) {
#pragma omp simd
  for (int i = 0; i < nx - 1; ++i) v[i] += c * (sxy[i + 1] - sxy[i] + syy_up[i] - syy_dn[i]);
  v[nx - 1] += c * (sxy[0] - sxy[nx - 1] + syy_up[nx - 1] - syy_dn[nx - 1]);
}

// s_xx, s_yy row j from v_x row j and v_y rows j, j-1.
inline void update_normal_row(double* __restrict sxx, double* __restrict syy, const double* __restrict vx,
                              const double* __restrict vy_up, const double* __restrict vy_dn, double dt,
                              double M, double lambda, double inv_h, int nx) {
#pragma omp simd
  for (int i = 0; i < nx - 1; ++i) {
    const double exx = (vx[i + 1] - vx[i]) * inv_h, eyy = (vy_up[i] - vy_dn[i]) * inv_h;
    sxx[i] += dt * (M * exx + lambda * eyy);
    syy[i] += dt * (lambda * exx + M * eyy);
  }
  const int i = nx - 1;
  const double exx = (vx[0] - vx[i]) * inv_h, eyy = (vy_up[i] - vy_dn[i]) * inv_h;
  sxx[i] += dt * (M * exx + lambda * eyy);
  syy[i] += dt * (lambda * exx + M * eyy);
}

// s_xx on the interface row (s_yy = 0 there): d s_xx/dt = Mb d v_x/dx.
inline void update_interface_sxx(double* __restrict sxx, const double* __restrict vx, double c, int nx) {
#pragma omp simd
  for (int i = 0; i < nx - 1; ++i) sxx[i] += c * (vx[i + 1] - vx[i]);
  sxx[nx - 1] += c * (vx[0] - vx[nx - 1]);
}

// s_xy row j (at y = (j+1/2) h) from v_x rows j, j+1 and v_y row j.
inline void update_sxy_row(double* __restrict s, const double* __restrict vx_dn, const double* __restrict vx_up,
                           const double* __restrict vy, double c, int nx) {
  s[0] += c * (vx_up[0] - vx_dn[0] + vy[0] - vy[nx - 1]);
#pragma omp simd
  for (int i = 1; i < nx; ++i) s[i] += c * (vx_up[i] - vx_dn[i] + vy[i] - vy[i - 1]);
}

// s_yz row j (antiplane, at y = (j+1/2) h) from v_z rows j, j+1: d s_yz/dt = mu d v_z/dy.
inline void update_syz_row(double* __restrict s, const double* __restrict vz_dn, const double* __restrict vz_up,
                           double c, int nx) {
#pragma omp simd
  for (int i = 0; i < nx; ++i) s[i] += c * (vz_up[i] - vz_dn[i]);
}

// One body of a two-body problem on the staggered grid, in its own frame (the
// interface is row 0, the outer face row ny).  Antiplane: vx holds v_z, sxx
// s_xz and sxy s_yz; vy and syy are unused.
struct BodyGrid {
  int ny, nx;
  double* vx;
  double* vy;
  double* sxx;
  double* syy;
  double* sxy;
  double rho, mu, lambda;
};

// Velocities t_{n-1/2} -> t_{n+1/2} off the interface row (v_x row ny: held at 0).
void body_velocities(const BodyGrid& b, bool antiplane, double dt, double h) {
  const std::size_t nxs = b.nx;
  const double c_v = dt / (b.rho * h);
  for (int j = 1; j < b.ny; ++j)
    update_vx_row(b.vx + j * nxs, b.sxx + j * nxs, b.sxy + j * nxs, b.sxy + (j - 1) * nxs, c_v, b.nx);
  if (antiplane) return;
  for (int j = 0; j < b.ny; ++j)  // s_yy row ny = 0 (driven outer face)
    update_vy_row(b.vy + j * nxs, b.sxy + j * nxs, b.syy + j * nxs, b.syy + (j + 1) * nxs, c_v, b.nx);
}

// Stresses t_n -> t_{n+1}; in-plane the interface row's s_xx, s_yy are left to
// the coupled interface update.
void body_stresses(const BodyGrid& b, bool antiplane, double dt, double h) {
  const std::size_t nxs = b.nx;
  const double inv_h = 1.0 / h, c_mu = dt * b.mu * inv_h;
  if (antiplane) {
    for (int j = 0; j < b.ny; ++j) update_interface_sxx(b.sxx + j * nxs, b.vx + j * nxs, c_mu, b.nx);  // s_xz
    for (int j = 0; j < b.ny; ++j) update_syz_row(b.sxy + j * nxs, b.vx + j * nxs, b.vx + (j + 1) * nxs, c_mu, b.nx);
    return;
  }
  const double M = b.lambda + 2 * b.mu;
  for (int j = 1; j < b.ny; ++j)
    update_normal_row(b.sxx + j * nxs, b.syy + j * nxs, b.vx + j * nxs, b.vy + j * nxs, b.vy + (j - 1) * nxs, dt, M,
                      b.lambda, inv_h, b.nx);
  for (int j = 0; j < b.ny; ++j)
    update_sxy_row(b.sxy + j * nxs, b.vx + j * nxs, b.vx + (j + 1) * nxs, b.vy + j * nxs, c_mu, b.nx);
}

// sigma_eff over a step of d sigma_eff/dt = -r (sigma_eff - sigma(t)) with sigma
// linear in t from sigma_old to sigma_new and r held fixed (exact for that).
double relax_effective(double effective_old, double sigma_old, double sigma_new, double rate, double dt) {
  const double x = rate * dt;
  const double ramp = x > 0.0 ? -std::expm1(-x) / x : 1.0;  // (1 - e^-x) / x
  return sigma_new + (effective_old - sigma_old) * std::exp(-x) - (sigma_new - sigma_old) * ramp;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    Args args;
    for (int i = 1; i < argc; ++i) {
      std::string a = argv[i];
      if (a == "-h" || a == "--help") {
        usage();
        return 0;
      }
      const auto eq = a.find('=');
      if (eq == std::string::npos) {
        usage();
        throw std::invalid_argument("argument '" + a + "' is not key=value");
      }
      args.kv[a.substr(0, eq)] = a.substr(eq + 1);
    }

    // --- parameters -----------------------------------------------------------
    const double L = args.num("length", 0, true), H = args.num("height", 0, true);
    const int nx = static_cast<int>(args.num("nx", 0, true));
    if (nx < 2) throw std::invalid_argument("nx must be at least 2");
    const double h = L / nx;
    const int ny = static_cast<int>(std::lround(H / h));
    if (ny < 1 || std::abs(ny * h - H) > 1e-9 * H)
      throw std::invalid_argument("height / (length / nx) must be a whole number");
    const double mu = args.num("shear_modulus", 0, true), nu = args.num("poisson_ratio", 0, true);
    const double rho = args.num("density", 0, true);
    const std::string plane = args.str("plane", "strain");
    const bool antiplane = plane == "antiplane";
    if (plane != "strain" && plane != "stress" && !antiplane)
      throw std::invalid_argument("plane = '" + plane + "': allowed are strain, stress, antiplane");
    const double lambda = lame_lambda(mu, nu, plane);
    const double cs = std::sqrt(mu / rho), cd = std::sqrt((lambda + 2 * mu) / rho);
    // The bottom body (docs/benchmarks/volume_bodies.md): the mirror image of the
    // top one (the single-strip scheme above), another elastic strip, or rigid.
    const std::string bottom_kind = args.str("bottom", "mirror");
    if (bottom_kind != "mirror" && bottom_kind != "elastic" && bottom_kind != "rigid")
      throw std::invalid_argument("bottom = '" + bottom_kind + "': allowed are mirror, elastic, rigid");
    const bool rigid_bottom = bottom_kind == "rigid";
    const bool two_bodies = bottom_kind != "mirror" || antiplane;
    const bool elastic_bottom = two_bodies && !rigid_bottom;
    const double mu_b = args.num("bottom_shear_modulus", mu), nu_b = args.num("bottom_poisson_ratio", nu);
    const double rho_b = args.num("bottom_density", rho), H_b = args.num("bottom_height", H);
    if (bottom_kind == "mirror" && (mu_b != mu || nu_b != nu || rho_b != rho || H_b != H))
      throw std::invalid_argument("bottom_* values differ from the top body's but bottom = mirror; give bottom=elastic");
    if (!(mu_b > 0) || !(rho_b > 0) || !(nu_b > -1 && nu_b < 0.5))
      throw std::invalid_argument("bottom_shear_modulus and bottom_density must be > 0, bottom_poisson_ratio in (-1, 0.5)");
    const int ny_b = elastic_bottom ? static_cast<int>(std::lround(H_b / h)) : 0;
    if (elastic_bottom && (ny_b < 1 || std::abs(ny_b * h - H_b) > 1e-9 * H_b))
      throw std::invalid_argument("bottom_height / (length / nx) must be a whole number");
    const double lambda_b = lame_lambda(mu_b, nu_b, plane);
    const double cs_b = std::sqrt(mu_b / rho_b), cd_b = std::sqrt((lambda_b + 2 * mu_b) / rho_b);
    // The fastest wave of the grid: sets the CFL limit and the default step.
    const double c_max = antiplane ? (elastic_bottom ? std::max(cs, cs_b) : cs)
                                   : (elastic_bottom ? std::max(cd, cd_b) : cd);
    const double normal_stress_slip_arg = args.num("normal_stress_slip", 0.0);
    const double normal_stress_time = args.num("normal_stress_time", 0.0);
    if (normal_stress_slip_arg < 0 || normal_stress_time < 0)
      throw std::invalid_argument("normal_stress_slip and normal_stress_time must be >= 0");
    const double v0 = args.num("driving_velocity", 0, true);
    const double sigma0 = args.num("normal_stress", 0, true);

    slipstrip::FrictionParameters f;
    f.strength_law = slipstrip::parse_strength_law(args.str("law", "paper"));
    f.state_law = slipstrip::parse_state_law(args.str("state_law", "aging"));
    f.f0 = args.num("f0", f.f0);
    f.a = args.num("a", f.a);
    f.b = args.num("b", f.b);
    f.characteristic_slip = args.num("characteristic_slip", f.characteristic_slip);
    f.v_star = args.num("v_star", f.v_star);
    f.phi_star = args.num("phi_star", f.phi_star);
    slipstrip::validate(f);

    const double P0 = args.num("load_pulse_amplitude", 0.0);
    const double x0 = args.num("pulse_center", 0.0), w = args.num("pulse_width", INFINITY);
    const double T = args.num("rise_time", 1e-4);
    const double la = args.num("local_amplitude", 0.0), lc = args.num("local_center", 0.0),
                 lw = args.num("local_width", 0.0);
    const std::string initial_file = args.str("initial_state", "");
    if (!initial_file.empty() && la != 0.0)
      throw std::invalid_argument("initial_state and local_amplitude exclude each other (the file is phi itself)");

    const double t_end = args.num("duration", 0, true);
    double dt = args.num("dt", 0.0);
    if (dt <= 0) dt = args.num("cfl", 0.5) * h / c_max;
    if (c_max * dt / h > 1.0 / std::sqrt(2.0) + 1e-12)
      throw std::invalid_argument(antiplane ? "dt above the CFL limit h / (sqrt(2) c_s) (the faster body's c_s)"
                                            : "dt above the CFL limit h / (sqrt(2) c_d) (the faster body's c_d)");
    const long nsteps = std::lround(t_end / dt);
    dt = t_end / nsteps;  // land exactly on t_end

    const std::vector<double> stations = parse_list(args.str("stations", ""));
    std::vector<int> station_nodes;
    for (double xs : stations) {
      const double r = xs / h;
      const long k = std::lround(r);
      if (std::abs(r - k) > 1e-6) throw std::invalid_argument("station x = " + std::to_string(xs) + " is not a grid node");
      station_nodes.push_back(static_cast<int>(((k % nx) + nx) % nx));
    }
    const std::string out = args.str("out", "volume_stations.txt");
    const long every = std::max(1L, static_cast<long>(args.num("output_every", 1)));
    const std::string profile_file = args.str("final_profile", "");
    const std::string snapshot_path = args.str("snapshot_file", "");
    const double snapshot_interval = args.num("snapshot_interval", 0.0);
    const std::string timeseries_path = args.str("timeseries_file", "");
    const double timeseries_interval = args.num("timeseries_interval", 0.0);
    const double progress_s = args.num("progress", 0.0);
    if (!snapshot_path.empty() && !(snapshot_interval > 0))
      throw std::invalid_argument("snapshot_file needs snapshot_interval > 0 (seconds)");
    if (!timeseries_path.empty() && !(timeseries_interval > 0))
      throw std::invalid_argument("timeseries_file needs timeseries_interval > 0 (seconds)");
    const bool stick_fix = args.num("stick_hold", 1.0) != 0.0;
    const std::string checkpoint_path = args.str("checkpoint", "");
    const double checkpoint_interval = args.num("checkpoint_interval", 0.0);
    const long checkpoint_steps = static_cast<long>(args.num("checkpoint_steps", 0.0));
    const long halt_step = static_cast<long>(args.num("halt_after_steps", 0.0));
    const bool resume = args.num("resume", 0.0) != 0.0;
    if (checkpoint_path.empty() && (checkpoint_interval > 0 || checkpoint_steps > 0 || halt_step > 0 || resume))
      throw std::invalid_argument("checkpoint_interval, checkpoint_steps, halt_after_steps and resume need checkpoint=FILE");
    for (auto& [k, v] : args.kv)
      if (!args.used.count(k)) throw std::invalid_argument("unknown argument " + k);
    // What a checkpoint must agree with to be resumed: every argument but the restart ones.
    std::string run_identity;
    for (const auto& [k, v] : args.kv)
      if (k != "checkpoint" && k != "checkpoint_interval" && k != "checkpoint_steps" && k != "halt_after_steps" &&
          k != "resume" && k != "progress")
        run_identity += k + "=" + v + "\n";

    // --- fields ---------------------------------------------------------------
    const std::size_t nxs = nx;
    std::vector<double> vx((ny + 1) * nxs, 0.0), vy(ny * nxs, 0.0), sxx((ny + 1) * nxs, 0.0),
        syy((ny + 1) * nxs, 0.0), sxy(ny * nxs, 0.0);
    std::vector<double> phi(nxs), slip(nxs, 0.0), V(nxs, v0), tau(nxs), pulse_shape(nxs, 0.0);
    std::vector<double> tau_h(nxs), v_mid(nxs);  // work arrays of the interface phase
    // normal stress (compressive, at the nodes) and the friction's effective one:
    // sigma0 throughout for a mirror pair and antiplane.
    std::vector<double> sigma(nxs, sigma0), sigma_eff(nxs, sigma0);
    // The bottom body's fields, in its own frame (two bodies with an elastic bottom).
    const std::size_t rows_b = ny_b;
    std::vector<double> vx_b((rows_b + 1) * nxs, 0.0), vy_b(rows_b * nxs, 0.0), sxx_b((rows_b + 1) * nxs, 0.0),
        syy_b((rows_b + 1) * nxs, 0.0), sxy_b(rows_b * nxs, 0.0);
    // Everything a step reads that an earlier step wrote (the restart state).
    const std::vector<std::vector<double>*> restart_fields = {&vx,   &vy,  &sxx, &syy,   &sxy,       &vx_b,
                                                              &vy_b, &sxx_b, &syy_b, &sxy_b, &phi, &slip,
                                                              &V,    &tau, &sigma, &sigma_eff, &v_mid};
    const double phi_ss = slipstrip::steady_state(f, v0);
    const double tau_ref = slipstrip::frictional_strength(f, sigma0, v0, phi_ss);
    for (int i = 0; i < nx; ++i) {
      const double x = i * h;
      phi[i] = phi_ss;
      tau[i] = tau_ref;
      if (la != 0.0 && lw > 0) {
        const double d = std::remainder(x - lc, L);
        phi[i] *= 1.0 + la * std::exp(-0.5 * d * d / (lw * lw));
      }
      if (P0 != 0.0) {
        double s = 1.0;
        if (std::isfinite(w) && w > 0) {
          const double d = std::remainder(x - x0, L);
          s = std::exp(-0.5 * d * d / (w * w));
        }
        pulse_shape[i] = P0 * s;
      }
    }
    if (!initial_file.empty()) {
      const File in = open_file(initial_file, "rb");
      if (std::fread(phi.data(), sizeof(double), nxs, in.get()) != nxs || std::fgetc(in.get()) != EOF)
        throw std::invalid_argument("initial_state " + initial_file + " must hold exactly nx = " +
                                    std::to_string(nx) + " float64 values");
      for (int i = 0; i < nx; ++i)
        if (!(phi[i] > 0) || !std::isfinite(phi[i]))
          throw std::invalid_argument("initial_state " + initial_file + ": phi at node " + std::to_string(i) +
                                      " is not finite and > 0");
    }
    auto profile = [&](double t) {
      if (t <= 0 || t >= T) return 0.0;
      const double s = std::sin(pi * t / T);
      return s * s * s * s;
    };

    const double c_rho = dt / rho, inv_h = 1.0 / h;
    const double M = lambda + 2 * mu, Mb = 4 * mu * (lambda + mu) / (lambda + 2 * mu);
    const double eta_h = rho * h / (2 * dt);
    const double c_v = c_rho * inv_h, c_xy = dt * mu * inv_h, c_b = dt * Mb * inv_h;

    // --- restart ------------------------------------------------------------------
    // A checkpoint is taken at the end of a step: the fields above, the step to
    // start at, the output counters and the byte sizes of the three output files.
    struct Counters {
      std::int64_t n_next = 0, snap_k = 0, ts_k = 0, next_snap = -1, next_ts = -1;
      std::int64_t bytes_out = 0, bytes_snap = 0, bytes_ts = 0;
    } resumed;
    const char magic[8] = {'S', 'L', 'P', 'V', 'O', 'L', 'C', '1'};
    if (resume) {
      const File in = open_file(checkpoint_path, "rb");
      char m[8];
      std::uint64_t len = 0;
      bool ok = std::fread(m, 1, 8, in.get()) == 8 && std::equal(m, m + 8, magic) &&
                std::fread(&len, sizeof len, 1, in.get()) == 1 && len < (1u << 20);
      std::string identity(ok ? len : 0, '\0');
      ok = ok && std::fread(identity.data(), 1, len, in.get()) == len;
      if (!ok) throw std::invalid_argument("checkpoint " + checkpoint_path + " is not a slipstrip_volume checkpoint");
      if (identity != run_identity)
        throw std::invalid_argument("checkpoint " + checkpoint_path + " was written by a run with other arguments");
      ok = std::fread(&resumed, sizeof resumed, 1, in.get()) == 1;
      for (std::vector<double>* field : restart_fields) {
        std::uint64_t n = 0;
        ok = ok && std::fread(&n, sizeof n, 1, in.get()) == 1 && n == field->size() &&
             std::fread(field->data(), sizeof(double), n, in.get()) == n;
      }
      if (!ok || std::fgetc(in.get()) != EOF)
        throw std::invalid_argument("checkpoint " + checkpoint_path + " is truncated or does not match the grid");
      // Cut the outputs back to what they held at the checkpoint; they are appended to.
      auto cut = [](const std::string& path, std::int64_t bytes) {
        if (path.empty()) return;
        if (!std::filesystem::exists(path) || static_cast<std::int64_t>(std::filesystem::file_size(path)) < bytes)
          throw std::invalid_argument("resume: " + path + " holds less than at the checkpoint");
        std::filesystem::resize_file(path, static_cast<std::uintmax_t>(bytes));
      };
      cut(out, resumed.bytes_out);
      cut(snapshot_path, resumed.bytes_snap);
      cut(timeseries_path, resumed.bytes_ts);
    }

    std::ofstream os(out, resume ? std::ios::app : std::ios::trunc);
    if (!os) throw std::runtime_error("cannot write " + out);
    if (!resume)
    os << "# slipstrip_volume: staggered-grid FD, L=" << L << " H=" << H << " nx=" << nx
       << " ny=" << ny << " h=" << h << " dt=" << std::setprecision(17) << dt
       << " c_d dt/h=" << cd * dt / h << " c_s=" << cs << " c_d=" << cd << " plane=" << plane
       << " bottom=" << bottom_kind << " ny_b=" << ny_b << " c_max dt/h=" << c_max * dt / h << "\n";
    if (!resume)
    os << "# columns: time [s], then per station x: slip [m], slip_rate [m/s], shear_stress [Pa], state [s], "
          "normal_stress [Pa], effective_normal_stress [Pa]\n";
    if (!resume) {
      os << "# stations:";
      for (double xs : stations) os << " " << xs;
      os << "\n";
    }
    os << std::setprecision(15) << std::scientific << std::flush;

    File snap_out, ts_out;
    if (!snapshot_path.empty()) snap_out = open_file(snapshot_path, resume ? "ab" : "wb");
    if (!timeseries_path.empty()) ts_out = open_file(timeseries_path, resume ? "ab" : "wb");

    auto write_row = [&](double t) {
      os << t;
      for (int k : station_nodes)
        os << " " << slip[k] << " " << V[k] << " " << tau[k] << " " << phi[k] << " " << sigma[k] << " "
           << sigma_eff[k];
      os << "\n";
    };
    auto write_snapshot = [&](double t) {
      std::FILE* fp = snap_out.get();
      bool ok = std::fwrite(&t, sizeof t, 1, fp) == 1;
      for (const std::vector<double>* field : {&slip, &V, &phi, &tau})
        ok = ok && std::fwrite(field->data(), sizeof(double), nxs, fp) == nxs;
      if (!ok || std::fflush(fp) != 0) throw std::runtime_error("cannot write " + snapshot_path);
    };
    auto write_timeseries = [&](double t) {
      double vmax = 0, slip_sum = 0, tau_sum = 0;
      for (int i = 0; i < nx; ++i) {
        vmax = std::max(vmax, std::abs(V[i]));
        slip_sum += slip[i];
        tau_sum += tau[i];
      }
      const double row[4] = {t, vmax, slip_sum / nx, tau_sum / nx};
      if (std::fwrite(row, sizeof(double), 4, ts_out.get()) != 4)
        throw std::runtime_error("cannot write " + timeseries_path);
    };

    // --- time loop ---------------------------------------------------------------
    // One parallel region; the three phases of a step (velocities of the bulk,
    // the interface nodes, the stresses) are work-shared loops separated by
    // barriers.  Output and checks run on one thread (omp single).  Errors from
    // inside the region are recorded and rethrown after it (an exception must
    // not leave an OpenMP region).
    // Blocks of interface nodes: a multiple of the batch width, a few per thread.
    const int block = 256;
    const int n_blocks = (nx + block - 1) / block;
    const slipstrip::LocalSolveParameters solve_params(f, sigma0, eta_h);
    std::string error;
    bool stop = false;
    auto record_error = [&](const std::exception& e, int node, long step) {
#pragma omp critical
      {
        if (error.empty())
          error = std::string(e.what()) + " at node " + std::to_string(node) + ", step " + std::to_string(step);
        stop = true;
      }
    };
    long snap_k = 0, ts_k = 0;
    long next_snap = snap_out ? sample_step(0, snapshot_interval, dt) : -1;
    long next_ts = ts_out ? sample_step(0, timeseries_interval, dt) : -1;
    const long n_start = resume ? resumed.n_next : 0;
    if (resume) {
      snap_k = resumed.snap_k, ts_k = resumed.ts_k, next_snap = resumed.next_snap, next_ts = resumed.next_ts;
    }
    const auto wall0 = std::chrono::steady_clock::now();
    double next_progress = progress_s;
    double next_checkpoint = checkpoint_interval;
    bool checkpoint_now = false, halted = false;
    // Written to FILE.partial and renamed, so a run killed while writing keeps the previous one.
    auto save_checkpoint = [&](long n_next) {
      os.flush();
      if (!os) throw std::runtime_error("cannot write " + out);
      for (std::FILE* fp : {snap_out.get(), ts_out.get()})
        if (fp && std::fflush(fp) != 0) throw std::runtime_error("cannot flush an output file");
      Counters c{n_next, snap_k, ts_k, next_snap, next_ts, static_cast<std::int64_t>(os.tellp()),
                 snap_out ? static_cast<std::int64_t>(std::ftell(snap_out.get())) : 0,
                 ts_out ? static_cast<std::int64_t>(std::ftell(ts_out.get())) : 0};
      const std::string tmp = checkpoint_path + ".partial";
      {
        const File fo = open_file(tmp, "wb");
        const std::uint64_t len = run_identity.size();
        bool ok = std::fwrite(magic, 1, 8, fo.get()) == 8 && std::fwrite(&len, sizeof len, 1, fo.get()) == 1 &&
                  std::fwrite(run_identity.data(), 1, len, fo.get()) == len &&
                  std::fwrite(&c, sizeof c, 1, fo.get()) == 1;
        for (const std::vector<double>* field : restart_fields) {
          const std::uint64_t n = field->size();
          ok = ok && std::fwrite(&n, sizeof n, 1, fo.get()) == 1 &&
               std::fwrite(field->data(), sizeof(double), n, fo.get()) == n;
        }
        if (!ok || std::fflush(fo.get()) != 0) throw std::runtime_error("cannot write " + tmp);
      }
      std::filesystem::rename(tmp, checkpoint_path);
    };
    // The outputs at step n (one thread).
    auto record = [&](long n, double t) {
      if (n % every == 0 || n == nsteps) write_row(t);
      // (an interval shorter than dt samples every step: skip the sample times this step covered)
      if (n == next_snap) {
        write_snapshot(t);
        while (next_snap <= n) next_snap = sample_step(++snap_k, snapshot_interval, dt);
      }
      if (n == next_ts) {
        write_timeseries(t);
        while (next_ts <= n) next_ts = sample_step(++ts_k, timeseries_interval, dt);
      }
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
      if (progress_s > 0 && wall >= next_progress) {
        std::fprintf(stderr, "step %ld / %ld  t = %.6g s  wall %.0f s\n", n, nsteps, t, wall);
        next_progress += progress_s;
      }
      // a checkpoint at the end of this step (read by every thread after the barriers)
      checkpoint_now = false;
      if (!checkpoint_path.empty() && n < nsteps) {
        if (checkpoint_interval > 0 && wall >= next_checkpoint) {
          checkpoint_now = true;
          next_checkpoint = wall + checkpoint_interval;
        }
        if ((checkpoint_steps > 0 && (n + 1) % checkpoint_steps == 0) || (halt_step > 0 && n + 1 == halt_step))
          checkpoint_now = true;
      }
    };
    // At the end of step n (all fields at the start of step n + 1).
    auto end_of_step = [&](long n) {
      save_checkpoint(n + 1);
      if (halt_step > 0 && n + 1 == halt_step) halted = true;
    };
    if (!two_bodies) {
    const double* sxx_p = sxx.data();
    const double* syy_p = syy.data();
    const double* sxy_p = sxy.data();
    double* vx_p = vx.data();
    double* vy_p = vy.data();
#pragma omp parallel
    {
      for (long n = n_start; n <= nsteps; ++n) {
        const double t = n * dt;
        // interface row: friction at t_n, in blocks of nodes (the batch solve
        // vectorises over the nodes of a block).
        const double g = profile(t);
#pragma omp for schedule(static)
        for (int blk = 0; blk < n_blocks; ++blk) {
          const int i0 = blk * block, i1 = std::min(nx, i0 + block);
          const std::size_t cnt = i1 - i0;
          for (int i = i0; i < i1; ++i) {
            const int im = i == 0 ? nx - 1 : i - 1;
            const double A = 0.5 * (sxx_p[i] - sxx_p[im]) + sxy_p[i];
            tau_h[i] = tau_ref + pulse_shape[i] * g + A + eta_h * (v0 + 2 * vx_p[i]);
          }
          try {
            // V^n from the previous V as the initial guess; V is overwritten in place.
            slipstrip::solve_slip_rate_batch(solve_params, std::span(tau_h).subspan(i0, cnt),
                                             std::span(phi).subspan(i0, cnt), std::span(V).subspan(i0, cnt),
                                             std::span(V).subspan(i0, cnt));
          } catch (const slipstrip::BatchFailure& e) {
            record_error(e, i0 + static_cast<int>(e.index), n);
            continue;
          }
          for (int i = i0; i < i1; ++i) {
            const double Vn = V[i], v_old = vx_p[i];
            tau[i] = tau_h[i] - eta_h * Vn;
            vx_p[i] = Vn - v0 - v_old;  // v_x^{n+1/2}
            if (Vn == 0.0 && stick_fix) {
              // Stuck at t_n.  Imposing only the time-centred V^n = 0 would make the
              // half-step slip rates alternate (V^{n+1/2} = -V^{n-1/2}); instead hold
              // V^{n+1/2} = 0 when the traction that does so, tau_h - eta_h V^{n-1/2}/2
              // (the half-cell momentum balance), is within the static strength.
              const double tau_stick = tau_h[i] - 0.5 * eta_h * (v0 + 2 * v_old);
              if (std::abs(tau_stick) <= slipstrip::frictional_strength(f, sigma0, 0.0, phi[i])) {
                tau[i] = tau_stick;
                vx_p[i] = -0.5 * v0;
              }
            }
            if (!std::isfinite(Vn) || !std::isfinite(tau[i]))
              record_error(std::runtime_error("non-finite slip rate or shear stress"), i, n);
          }
        }
        // (implicit barrier: the interface and every velocity are at t_{n+1/2})
#pragma omp single
        {
          try {
            record(n, t);
          } catch (const std::exception& e) {
            error = e.what();
            stop = true;
          }
        }
        if (stop || n == nsteps) break;
        // state and slip t_n -> t_{n+1} with the mid-step slip rate V^{n+1/2}.
#pragma omp for schedule(static) nowait
        for (int blk = 0; blk < n_blocks; ++blk) {
          const int i0 = blk * block, i1 = std::min(nx, i0 + block);
          const std::size_t cnt = i1 - i0;
          for (int i = i0; i < i1; ++i) {
            v_mid[i] = v0 + 2 * vx_p[i];
            slip[i] += dt * v_mid[i];
          }
          try {
            slipstrip::evolve_state_batch(f, std::span(phi).subspan(i0, cnt), std::span(v_mid).subspan(i0, cnt), dt,
                                          std::span(phi).subspan(i0, cnt));
          } catch (const slipstrip::BatchFailure& e) {
            record_error(e, i0 + static_cast<int>(e.index), n);
          }
        }
        // The bulk: velocities t_{n-1/2} -> t_{n+1/2} from the stresses at t_n
        // (the interface row's v_x is done above: it needs only row 0), then
        // the stresses t_n -> t_{n+1} from those velocities.
        auto velocity_vx = [&](int j) {  // rows 1..ny-1 (row 0: friction; row ny: held at 0)
          update_vx_row(vx_p + j * nxs, sxx_p + j * nxs, sxy_p + j * nxs, sxy_p + (j - 1) * nxs, c_v, nx);
        };
        auto velocity_vy = [&](int j) {  // rows 0..ny-1
          update_vy_row(vy_p + j * nxs, sxy_p + j * nxs, syy_p + j * nxs, syy_p + (j + 1) * nxs, c_v, nx);
        };
        auto stress_normal = [&](int j) {  // rows 0..ny-1 (row ny: s_yy = 0, s_xx unused)
          if (j == 0)
            update_interface_sxx(sxx.data(), vx_p, c_b, nx);
          else
            update_normal_row(sxx.data() + j * nxs, syy.data() + j * nxs, vx_p + j * nxs, vy_p + j * nxs,
                              vy_p + (j - 1) * nxs, dt, M, lambda, inv_h, nx);
        };
        auto stress_shear = [&](int j) {  // rows 0..ny-1
          update_sxy_row(sxy.data() + j * nxs, vx_p + j * nxs, vx_p + (j + 1) * nxs, vy_p + j * nxs, c_xy, nx);
        };
        if (omp_get_num_threads() == 1) {
          // One sweep up the strip with the stresses one row behind the
          // velocities: row j's stresses need v_x of rows j, j+1 and v_y of rows
          // j-1, j at t_{n+1/2}, and no later velocity update reads row j's
          // stresses.  A few rows are live at a time (they stay in cache)
          // instead of every field being streamed through twice per step.
          // Each cell does the same arithmetic as in the split sweeps below.
          for (int j = 0; j < ny; ++j) {
            if (j + 1 < ny) velocity_vx(j + 1);
            velocity_vy(j);
            stress_normal(j);
            stress_shear(j);
          }
        } else {
#pragma omp for schedule(static) nowait
          for (int j = 1; j < ny; ++j) velocity_vx(j);
#pragma omp for schedule(static)
          for (int j = 0; j < ny; ++j) velocity_vy(j);
#pragma omp for schedule(static) nowait
          for (int j = 0; j < ny; ++j) stress_normal(j);
#pragma omp for schedule(static)
          for (int j = 0; j < ny; ++j) stress_shear(j);
        }
        if (checkpoint_now) {
#pragma omp single
          {
            try {
              end_of_step(n);
            } catch (const std::exception& e) {
              error = e.what();
            }
            stop = halted || !error.empty();
          }
          if (stop) break;
        }
      }
    }
    } else {
      // --- two bodies (the header's "Two bodies"); one thread ----------------------
      // The top body's fields are the arrays above (antiplane: vx = v_z, sxx =
      // s_xz, sxy = s_yz); the bottom body's, in its own frame, these.
      const BodyGrid top{ny, nx, vx.data(), vy.data(), sxx.data(), syy.data(), sxy.data(), rho, mu, lambda};
      const BodyGrid bot{ny_b, nx, vx_b.data(), vy_b.data(), sxx_b.data(), syy_b.data(), sxy_b.data(),
                         rho_b, mu_b, lambda_b};
      const double inv_rho_t = 1.0 / rho, inv_rho_b = elastic_bottom ? 1.0 / rho_b : 0.0;  // rigid: 1/rho_b = 0
      const double eta_2 = h / (dt * (inv_rho_t + inv_rho_b)), dt_h = dt / h;
      const double L_sigma = normal_stress_slip_arg > 0 ? normal_stress_slip_arg : f.characteristic_slip;
      const bool normal_coupling = !antiplane;
      // the interface row's split s_xx and common s_yy (in-plane)
      const double M_t = lambda + 2 * mu, M_b = lambda_b + 2 * mu_b;
      const double r_t = lambda / M_t, r_b = elastic_bottom ? lambda_b / M_b : 0.0;
      const double compliance = 1.0 / M_t + (elastic_bottom ? 1.0 / M_b : 0.0);
      double* v_t = vx.data();
      double* v_b = vx_b.data();
      for (long n = n_start; n <= nsteps; ++n) {
        const double t = n * dt;
        const double g = profile(t);
        for (int i = 0; i < nx; ++i) {
          const int im = i == 0 ? nx - 1 : i - 1;
          if (normal_coupling) {
            // sigma at the node (the mean of the two cells beside it) at t_n, and
            // sigma_eff advanced from t_{n-1} at the rate of V^{n-1/2} (v_mid).
            const double s_new = sigma0 - 0.5 * (syy[im] + syy[i]);
            if (n == 0) {
              sigma_eff[i] = s_new;
            } else {
              const double rate = normal_stress_time > 0 ? 1.0 / normal_stress_time
                                                         : (std::abs(v_mid[i]) + f.v_star) / L_sigma;
              sigma_eff[i] = relax_effective(sigma_eff[i], sigma[i], s_new, rate, dt);
            }
            sigma[i] = s_new;
            if (!(s_new > 0) || !(sigma_eff[i] > 0)) {
              std::ostringstream msg;
              msg << "interface opening at node " << i << " (x = " << i * h << " m), t = " << t << " s, step " << n
                  << ": normal stress " << s_new << " Pa, effective " << sigma_eff[i]
                  << " Pa; opening is not modelled, so the run stops";
              throw std::runtime_error(msg.str());
            }
          }
          const double A_t = 0.5 * (sxx[i] - sxx[im]) + sxy[i];
          const double A_b = elastic_bottom ? 0.5 * (sxx_b[i] - sxx_b[im]) + sxy_b[i] : 0.0;
          const double v_rel = v0 + v_t[i] - (elastic_bottom ? v_b[i] : 0.0);  // v0 + v_t - v_b at t_{n-1/2}
          const double v_free = v_rel + dt_h * (A_t * inv_rho_t - A_b * inv_rho_b);
          const double load = tau_ref + pulse_shape[i] * g;
          tau_h[i] = load + eta_2 * v_free;
          double Vn;
          try {
            Vn = slipstrip::solve_slip_rate(f, sigma_eff[i], eta_2, tau_h[i], phi[i], V[i]);
          } catch (const std::exception& e) {
            throw std::runtime_error(std::string(e.what()) + " at node " + std::to_string(i) + ", step " +
                                     std::to_string(n));
          }
          V[i] = Vn;
          double traction = eta_2 * (v_free - Vn);  // T = tau - tau_ref - P
          tau[i] = load + traction;
          if (Vn == 0.0 && stick_fix) {
            // as the mirror scheme: hold V^{n+1/2} = 0 if that traction is within the static strength
            const double t_stick = eta_2 * v_free - 0.5 * eta_2 * v_rel;
            if (std::abs(load + t_stick) <= slipstrip::frictional_strength(f, sigma_eff[i], 0.0, phi[i])) {
              traction = t_stick;
              tau[i] = load + t_stick;
            }
          }
          v_t[i] += 2 * dt_h * inv_rho_t * (A_t - traction);  // t_{n+1/2}
          if (elastic_bottom) v_b[i] += 2 * dt_h * inv_rho_b * (A_b + traction);
          if (!std::isfinite(Vn) || !std::isfinite(tau[i]))
            throw std::runtime_error("non-finite slip rate or shear stress at node " + std::to_string(i) +
                                     ", step " + std::to_string(n));
        }
        record(n, t);
        if (n == nsteps) break;
        for (int i = 0; i < nx; ++i) {
          v_mid[i] = v0 + v_t[i] - (elastic_bottom ? v_b[i] : 0.0);  // V^{n+1/2}
          slip[i] += dt * v_mid[i];
        }
        try {
          slipstrip::evolve_state_batch(f, std::span(phi), std::span(v_mid), dt, std::span(phi));
        } catch (const slipstrip::BatchFailure& e) {
          throw std::runtime_error(std::string(e.what()) + " at node " + std::to_string(e.index) + ", step " +
                                   std::to_string(n));
        }
        body_velocities(top, antiplane, dt, h);
        if (elastic_bottom) body_velocities(bot, antiplane, dt, h);
        if (normal_coupling) {
          // the interface row: one s_yy, s_xx on each side (the header's formula)
          for (int i = 0; i < nx; ++i) {
            const int ip = i == nx - 1 ? 0 : i + 1;
            const double exx_t = (v_t[ip] - v_t[i]) * inv_h;
            const double exx_b = elastic_bottom ? (v_b[ip] - v_b[i]) * inv_h : 0.0;
            const double e_avg = (vy[i] + (elastic_bottom ? vy_b[i] : 0.0)) * inv_h;
            const double dsyy = (2 * e_avg + r_t * exx_t + r_b * exx_b) / compliance;
            sxx[i] += dt * (lambda * (dsyy - lambda * exx_t) / M_t + M_t * exx_t);
            if (elastic_bottom) sxx_b[i] += dt * (lambda_b * (dsyy - lambda_b * exx_b) / M_b + M_b * exx_b);
            syy[i] += dt * dsyy;
          }
          if (elastic_bottom) std::copy(syy.begin(), syy.begin() + nx, syy_b.begin());
        }
        body_stresses(top, antiplane, dt, h);
        if (elastic_bottom) body_stresses(bot, antiplane, dt, h);
        if (checkpoint_now) {
          end_of_step(n);
          if (halted) break;
        }
      }
    }
    if (!error.empty()) throw std::runtime_error(error);
    if (halted) {
      std::cerr << "slipstrip_volume: halted after step " << halt_step << " of " << nsteps << "; checkpoint "
                << checkpoint_path << " (resume=1 continues)\n";
      return 3;
    }
    if (!profile_file.empty()) {
      std::ofstream ps(profile_file);
      ps << "# x [m], slip [m], slip_rate [m/s], shear_stress [Pa], state [s], normal_stress [Pa], "
            "effective_normal_stress [Pa] at t = "
         << std::setprecision(17) << t_end << "\n"
         << std::scientific << std::setprecision(15);
      for (int i = 0; i < nx; ++i)
        ps << i * h << " " << slip[i] << " " << V[i] << " " << tau[i] << " " << phi[i] << " " << sigma[i] << " "
           << sigma_eff[i] << "\n";
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "slipstrip_volume: error: " << e.what() << "\n";
    return 2;
  }
}
