// Interface FFT (r2c + c2r pair, as kernels/fft.cpp) with FFTW_ESTIMATE vs
// FFTW_MEASURE plans: planning time and time per pair at N = 1600 and 2048
// (docs/reliability.md, "Cost of FFTW_ESTIMATE").
#include <fftw3.h>
#include <chrono>
#include <cstdio>
#include <vector>
#include <algorithm>
int main() {
  for (int n : {1600, 2048}) {
    for (unsigned flag : {FFTW_ESTIMATE, FFTW_MEASURE}) {
      double* r = fftw_alloc_real(n); fftw_complex* c = fftw_alloc_complex(n / 2 + 1);
      auto t0 = std::chrono::steady_clock::now();
      fftw_plan f = fftw_plan_dft_r2c_1d(n, r, c, flag), b = fftw_plan_dft_c2r_1d(n, c, r, flag);
      double plan_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      for (int i = 0; i < n; ++i) r[i] = i % 7;
      std::vector<double> best;
      for (int rep = 0; rep < 7; ++rep) {
        auto s = std::chrono::steady_clock::now();
        for (int k = 0; k < 20000; ++k) { fftw_execute(f); fftw_execute(b); }
        best.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - s).count() / 20000);
      }
      std::sort(best.begin(), best.end());
      std::printf("N=%d %s: plan %.1f ms, r2c+c2r %.2f us (median of 7), min %.2f us\n", n, flag == FFTW_ESTIMATE ? "ESTIMATE" : "MEASURE ", plan_ms, best[3], best[0]);
      fftw_destroy_plan(f); fftw_destroy_plan(b); fftw_free(r); fftw_free(c);
    }
  }
}
