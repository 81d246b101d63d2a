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
#include <cstdlib>
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
      "  material : shear_modulus=mu poisson_ratio=nu density=rho plane=strain|stress\n"
      "  loading  : driving_velocity=v0 normal_stress=sigma0\n"
      "  friction : law=paper|dieterich_ruina|regularized f0= a= b= characteristic_slip= v_star= phi_star=\n"
      "             state_law=aging|slip\n"
      "  pulse    : load_pulse_amplitude=P0 pulse_center=x0 pulse_width=w rise_time=T (sin^4 bump on [0,T])\n"
      "  initial  : local_amplitude= local_center= local_width= (Gaussian change of phi, relative)\n"
      "             initial_state=FILE (phi at the nx interface nodes, nx raw float64; replaces local_*)\n"
      "  time     : duration=t_end cfl=c (dt = c h / c_d, default 0.5; or dt=...) \n"
      "  output   : stations=x1,x2,... (on grid nodes) out=FILE output_every=k final_profile=FILE\n"
      "             snapshot_file=FILE snapshot_interval=s (records: t, slip[nx], slip_rate[nx],\n"
      "               state[nx], shear_stress[nx], raw float64, appended and flushed per snapshot)\n"
      "             timeseries_file=FILE timeseries_interval=s (records: t, max slip rate, mean slip,\n"
      "               mean shear stress, raw float64)\n"
      "             progress=s (seconds of wall time between progress lines on stderr; 0 = off)\n"
      "  interface: stick_hold=1|0 (hold V^{n+1/2} = 0 at stuck nodes; default 1)\n"
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
    double lambda;
    if (plane == "strain")
      lambda = 2 * mu * nu / (1 - 2 * nu);
    else if (plane == "stress")
      lambda = 2 * mu * nu / (1 - nu);  // thin plate, sigma_zz = 0
    else
      throw std::invalid_argument("plane must be strain or stress");
    const double cs = std::sqrt(mu / rho), cd = std::sqrt((lambda + 2 * mu) / rho);
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
    if (dt <= 0) dt = args.num("cfl", 0.5) * h / cd;
    if (cd * dt / h > 1.0 / std::sqrt(2.0) + 1e-12)
      throw std::invalid_argument("dt above the CFL limit h / (sqrt(2) c_d)");
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
    for (auto& [k, v] : args.kv)
      if (!args.used.count(k)) throw std::invalid_argument("unknown argument " + k);

    // --- fields ---------------------------------------------------------------
    const std::size_t nxs = nx;
    std::vector<double> vx((ny + 1) * nxs, 0.0), vy(ny * nxs, 0.0), sxx((ny + 1) * nxs, 0.0),
        syy((ny + 1) * nxs, 0.0), sxy(ny * nxs, 0.0);
    std::vector<double> phi(nxs), slip(nxs, 0.0), V(nxs, v0), tau(nxs), pulse_shape(nxs, 0.0);
    std::vector<double> tau_h(nxs), v_mid(nxs);  // work arrays of the interface phase
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

    std::ofstream os(out);
    if (!os) throw std::runtime_error("cannot write " + out);
    os << "# slipstrip_volume: staggered-grid FD, L=" << L << " H=" << H << " nx=" << nx
       << " ny=" << ny << " h=" << h << " dt=" << std::setprecision(17) << dt
       << " c_d dt/h=" << cd * dt / h << " c_s=" << cs << " c_d=" << cd << "\n";
    os << "# columns: time [s], then per station x: slip [m], slip_rate [m/s], shear_stress [Pa], state [s]\n";
    os << "# stations:";
    for (double xs : stations) os << " " << xs;
    os << "\n" << std::setprecision(15) << std::scientific << std::flush;

    File snap_out, ts_out;
    if (!snapshot_path.empty()) snap_out = open_file(snapshot_path, "wb");
    if (!timeseries_path.empty()) ts_out = open_file(timeseries_path, "wb");

    auto write_row = [&](double t) {
      os << t;
      for (int k : station_nodes) os << " " << slip[k] << " " << V[k] << " " << tau[k] << " " << phi[k];
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
    const auto wall0 = std::chrono::steady_clock::now();
    double next_progress = progress_s;
    const double* sxx_p = sxx.data();
    const double* syy_p = syy.data();
    const double* sxy_p = sxy.data();
    double* vx_p = vx.data();
    double* vy_p = vy.data();
#pragma omp parallel
    {
      for (long n = 0; n <= nsteps; ++n) {
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
            if (n % every == 0 || n == nsteps) write_row(t);
            if (n == next_snap) {
              write_snapshot(t);
              next_snap = sample_step(++snap_k, snapshot_interval, dt);
            }
            if (n == next_ts) {
              write_timeseries(t);
              next_ts = sample_step(++ts_k, timeseries_interval, dt);
            }
            if (progress_s > 0) {
              const double wall =
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
              if (wall >= next_progress) {
                std::fprintf(stderr, "step %ld / %ld  t = %.6g s  wall %.0f s\n", n, nsteps, t, wall);
                next_progress += progress_s;
              }
            }
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
      }
    }
    if (!error.empty()) throw std::runtime_error(error);
    if (!profile_file.empty()) {
      std::ofstream ps(profile_file);
      ps << "# x [m], slip [m], slip_rate [m/s], shear_stress [Pa], state [s] at t = "
         << std::setprecision(17) << t_end << "\n"
         << std::scientific << std::setprecision(15);
      for (int i = 0; i < nx; ++i)
        ps << i * h << " " << slip[i] << " " << V[i] << " " << tau[i] << " " << phi[i] << "\n";
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "slipstrip_volume: error: " << e.what() << "\n";
    return 2;
  }
}
