// slipstrip_volume: an independent 2D elastodynamic volume solver for the
// strip-pair problem, used only as a test oracle for the boundary-integral
// solver (docs/benchmarks/volume_solver.md).  It shares NOTHING with
// slipstrip's kernels (no strip response, no history operator, no FFT): the
// bulk is a staggered-grid velocity-stress finite-difference scheme
// (Virieux 1986), second order in space and time.  Only the friction law
// (strength, state evolution, scalar local solve) is taken from friction/,
// because the friction law is not what is being tested.
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
// solved by slipstrip::solve_slip_rate.  The state then advances with the
// exact constant-rate update over [t_n, t_{n+1}] at V^{n+1/2} = v0 + 2 v_x^{n+1/2}
// (midpoint rule: second order).  On row 0, s_yy = 0 gives
// d s_xx/dt = 4 mu (lambda + mu)/(lambda + 2 mu) d v_x/dx.
//
// Usage: slipstrip_volume key=value ...   (see usage() below)
// Output: a text file of station time series at t_n (every `output_every` steps)
// and, with final_profile=FILE, the interface fields at the end.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

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
      "  time     : duration=t_end cfl=c (dt = c h / c_d, default 0.5; or dt=...) \n"
      "  output   : stations=x1,x2,... (on grid nodes) out=FILE output_every=k final_profile=FILE\n"
      "  interface: stick_hold=1|0 (hold V^{n+1/2} = 0 at stuck nodes; default 1)\n";
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
    const bool stick_fix = args.num("stick_hold", 1.0) != 0.0;
    for (auto& [k, v] : args.kv)
      if (!args.used.count(k)) throw std::invalid_argument("unknown argument " + k);

    // --- fields ---------------------------------------------------------------
    const std::size_t nxs = nx;
    std::vector<double> vx((ny + 1) * nxs, 0.0), vy(ny * nxs, 0.0), sxx((ny + 1) * nxs, 0.0),
        syy((ny + 1) * nxs, 0.0), sxy(ny * nxs, 0.0);
    std::vector<double> phi(nxs), slip(nxs, 0.0), V(nxs, v0), tau(nxs), pulse_shape(nxs, 0.0);
    const double phi_ss = slipstrip::steady_state(f, v0);
    const double tau_ref = slipstrip::frictional_strength(f, sigma0, v0, phi_ss);
    for (int i = 0; i < nx; ++i) {
      const double x = i * h;
      phi[i] = phi_ss;
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
    auto profile = [&](double t) {
      if (t <= 0 || t >= T) return 0.0;
      const double s = std::sin(pi * t / T);
      return s * s * s * s;
    };

    const double c_rho = dt / rho, inv_h = 1.0 / h;
    const double M = lambda + 2 * mu, Mb = 4 * mu * (lambda + mu) / (lambda + 2 * mu);
    const double eta_h = rho * h / (2 * dt);

    std::ofstream os(out);
    if (!os) throw std::runtime_error("cannot write " + out);
    os << "# slipstrip_volume: staggered-grid FD, L=" << L << " H=" << H << " nx=" << nx
       << " ny=" << ny << " h=" << h << " dt=" << std::setprecision(17) << dt
       << " c_d dt/h=" << cd * dt / h << " c_s=" << cs << " c_d=" << cd << "\n";
    os << "# columns: time [s], then per station x: slip [m], slip_rate [m/s], shear_stress [Pa], state [s]\n";
    os << "# stations:";
    for (double xs : stations) os << " " << xs;
    os << "\n" << std::setprecision(15) << std::scientific;

    auto write_row = [&](double t) {
      os << t;
      for (int k : station_nodes) os << " " << slip[k] << " " << V[k] << " " << tau[k] << " " << phi[k];
      os << "\n";
    };

    // --- time loop ---------------------------------------------------------------
    for (long n = 0; n <= nsteps; ++n) {
      const double t = n * dt;
      // velocities t_{n-1/2} -> t_{n+1/2} from stresses at t_n.
      for (int j = 1; j < ny; ++j) {
        double* v = &vx[j * nxs];
        const double *a = &sxx[j * nxs], *up = &sxy[j * nxs], *dn = &sxy[(j - 1) * nxs];
        for (int i = 0; i < nx; ++i) {
          const int im = i == 0 ? nx - 1 : i - 1;
          v[i] += c_rho * inv_h * (a[i] - a[im] + up[i] - dn[i]);
        }
      }
      for (int j = 0; j < ny; ++j) {
        double* v = &vy[j * nxs];
        const double *s = &sxy[j * nxs], *a = &syy[j * nxs], *b = &syy[(j + 1) * nxs];
        for (int i = 0; i < nx; ++i) {
          const int ip = i == nx - 1 ? 0 : i + 1;
          v[i] += c_rho * inv_h * (s[ip] - s[i] + b[i] - a[i]);
        }
      }
      // interface row: friction at t_n.
      const double g = profile(t);
      for (int i = 0; i < nx; ++i) {
        const int im = i == 0 ? nx - 1 : i - 1;
        const double A = 0.5 * (sxx[i] - sxx[im]) + sxy[i];
        const double load = pulse_shape[i] * g;
        const double v_old = vx[i];
        const double tau_h = tau_ref + load + A + eta_h * (v0 + 2 * v_old);
        const double Vn = slipstrip::solve_slip_rate(f, sigma0, eta_h, tau_h, phi[i], V[i]);
        V[i] = Vn;
        tau[i] = tau_h - eta_h * Vn;
        vx[i] = Vn - v0 - v_old;  // v_x^{n+1/2}
        if (Vn == 0.0 && stick_fix) {
          // Stuck at t_n.  Imposing only the time-centred V^n = 0 would make the
          // half-step slip rates alternate (V^{n+1/2} = -V^{n-1/2}); instead hold
          // V^{n+1/2} = 0 when the traction that does so, tau_h - eta_h V^{n-1/2}/2
          // (the half-cell momentum balance), is within the static strength.
          const double tau_stick = tau_h - 0.5 * eta_h * (v0 + 2 * v_old);
          if (std::abs(tau_stick) <= slipstrip::frictional_strength(f, sigma0, 0.0, phi[i])) {
            tau[i] = tau_stick;
            vx[i] = -0.5 * v0;
          }
        }
      }
      if (n % every == 0 || n == nsteps) write_row(t);
      if (n == nsteps) break;
      // state and slip t_n -> t_{n+1} with the mid-step slip rate.
      for (int i = 0; i < nx; ++i) {
        const double Vh = v0 + 2 * vx[i];
        phi[i] = slipstrip::evolve_state(f, phi[i], Vh, dt);
        slip[i] += dt * Vh;
      }
      // stresses t_n -> t_{n+1} from velocities at t_{n+1/2}.
      {
        const double* v = &vx[0];
        double* a = &sxx[0];
        for (int i = 0; i < nx; ++i) {
          const int ip = i == nx - 1 ? 0 : i + 1;
          a[i] += dt * Mb * inv_h * (v[ip] - v[i]);
        }
      }
      for (int j = 1; j < ny; ++j) {
        const double *v = &vx[j * nxs], *b = &vy[j * nxs], *c = &vy[(j - 1) * nxs];
        double *a = &sxx[j * nxs], *s = &syy[j * nxs];
        for (int i = 0; i < nx; ++i) {
          const int ip = i == nx - 1 ? 0 : i + 1;
          const double exx = (v[ip] - v[i]) * inv_h, eyy = (b[i] - c[i]) * inv_h;
          a[i] += dt * (M * exx + lambda * eyy);
          s[i] += dt * (lambda * exx + M * eyy);
        }
      }
      for (int j = 0; j < ny; ++j) {
        const double *v0r = &vx[j * nxs], *v1r = &vx[(j + 1) * nxs], *b = &vy[j * nxs];
        double* s = &sxy[j * nxs];
        for (int i = 0; i < nx; ++i) {
          const int im = i == 0 ? nx - 1 : i - 1;
          s[i] += dt * mu * inv_h * (v1r[i] - v0r[i] + b[i] - b[im]);
        }
      }
      if (!std::isfinite(V[0]) || !std::isfinite(sxy[0]))
        throw std::runtime_error("non-finite field at step " + std::to_string(n));
    }
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
