// Compiled with -mavx2 -mfma (core/CMakeLists.txt). Only <immintrin.h> (static inline intrinsics),
// core/avx2_lanes.hpp (static functions) and this file's own functions: no inline function with
// external linkage (see core/vector_math_avx2.hpp).
#include "core/column_products_avx2.hpp"

#include "core/avx2_lanes.hpp"

namespace tofcomp::core::avx2 {
namespace {

// A tile of the product is kTileRows columns of x against kTileColumns columns of z: 8
// accumulators, enough independent fused multiply-adds to cover the FMA units' latency
// (two units, four cycles each), from 6 loads per 8 multiply-adds.
constexpr long kTileRows = 4;
constexpr long kTileColumns = 2;
// Ranges per pass: every tile of a product is visited within one pass, so the pass's ranges
// (kRowBlock × p doubles: 17 KB at p = 17) must stay in the L1 cache.
constexpr long kRowBlock = 128;

// The R × C sums s(r, c) = Σ_k x_r[k] z_c[k] over k < n, x_r = x + r·ldx, z_c = z + c·ldz, added
// to out(r, c) = out[r + c·ldo] where `keep(r, c)` (the Gram matrix keeps its lower triangle).
// R and C are template arguments so that the accumulators stay in registers.
template <long R, long C, typename Keep>
inline __attribute__((always_inline)) void add_tile(const double* x, long ldx, const double* z,
                                                    long ldz, long n, double* out, long ldo,
                                                    const Keep& keep) {
  // The loops over r and c are unrolled outright (GCC at -O2 does not unroll them by itself, and
  // the accumulators then live on the stack, one load and store per multiply-add).
  __m256d acc[R][C];
#pragma GCC unroll 4
  for (long r = 0; r < R; ++r) {
#pragma GCC unroll 2
    for (long c = 0; c < C; ++c) acc[r][c] = _mm256_setzero_pd();
  }
  long k = 0;
  for (; k + kLanes <= n; k += kLanes) {
    __m256d zk[C];
#pragma GCC unroll 2
    for (long c = 0; c < C; ++c) zk[c] = _mm256_loadu_pd(z + c * ldz + k);
#pragma GCC unroll 4
    for (long r = 0; r < R; ++r) {
      const __m256d xk = _mm256_loadu_pd(x + r * ldx + k);
#pragma GCC unroll 2
      for (long c = 0; c < C; ++c) acc[r][c] = _mm256_fmadd_pd(xk, zk[c], acc[r][c]);
    }
  }
  for (long r = 0; r < R; ++r) {
    for (long c = 0; c < C; ++c) {
      if (!keep(r, c)) continue;
      double s = horizontal_sum(acc[r][c]);
      for (long t = k; t < n; ++t) s += x[r * ldx + t] * z[c * ldz + t];
      out[r + c * ldo] += s;
    }
  }
}

// The tile at x's columns [i, i + rows) and z's [j, j + columns), rows ≤ kTileRows and
// columns ≤ kTileColumns, dispatched to its fixed-size kernel.
template <typename Keep>
void add_tile_of(long rows, long columns, const double* x, long ldx, const double* z, long ldz,
                 long n, double* out, long ldo, const Keep& keep) {
  if (columns == kTileColumns) {
    switch (rows) {
      case 4: return add_tile<4, 2>(x, ldx, z, ldz, n, out, ldo, keep);
      case 3: return add_tile<3, 2>(x, ldx, z, ldz, n, out, ldo, keep);
      case 2: return add_tile<2, 2>(x, ldx, z, ldz, n, out, ldo, keep);
      default: return add_tile<1, 2>(x, ldx, z, ldz, n, out, ldo, keep);
    }
  }
  switch (rows) {
    case 4: return add_tile<4, 1>(x, ldx, z, ldz, n, out, ldo, keep);
    case 3: return add_tile<3, 1>(x, ldx, z, ldz, n, out, ldo, keep);
    case 2: return add_tile<2, 1>(x, ldx, z, ldz, n, out, ldo, keep);
    default: return add_tile<1, 1>(x, ldx, z, ldz, n, out, ldo, keep);
  }
}

// Doubles in a 64-byte cache line.
constexpr long kDoublesPerLine = 8;

inline long smaller(long a, long b) { return a < b ? a : b; }

}  // namespace

void add_lower_gram(const double* x, long n, long p, long ldx, double* gram, long ldg) {
  for (long first = 0; first < n; first += kRowBlock) {
    const long rows = smaller(kRowBlock, n - first);
    const double* block = x + first;
    for (long j = 0; j < p; j += kTileColumns) {
      const long columns = smaller(kTileColumns, p - j);
      // The tiles on and below the diagonal: x's columns from j down.
      for (long i = j; i < p; i += kTileRows) {
        const long tile_rows = smaller(kTileRows, p - i);
        add_tile_of(tile_rows, columns, block + i * ldx, ldx, block + j * ldx, ldx, rows,
                    gram + i + j * ldg, ldg,
                    [i, j](long r, long c) { return i + r >= j + c; });
      }
    }
  }
}

void add_cross_products(const double* x, long n, long p, long ldx, const double* z, long q,
                        long ldz, double* out, long ldo) {
  const auto every = [](long, long) { return true; };
  for (long first = 0; first < n; first += kRowBlock) {
    const long rows = smaller(kRowBlock, n - first);
    for (long j = 0; j < q; j += kTileColumns) {
      const long columns = smaller(kTileColumns, q - j);
      for (long i = 0; i < p; i += kTileRows) {
        add_tile_of(smaller(kTileRows, p - i), columns, x + first + i * ldx, ldx,
                    z + first + j * ldz, ldz, rows, out + i + j * ldo, ldo, every);
      }
    }
  }
}

void scale_centred_rows(const double* h, long n, long p, long ldh, const double* centre,
                        const double* scale, double* x, long ldx) {
  for (long i = 0; i < p; ++i) {
    const double* column = h + i * ldh;
    double* out = x + i * ldx;
    const __m256d c = _mm256_set1_pd(centre[i]);
    long k = 0;
    for (; k + kLanes <= n; k += kLanes) {
      _mm256_storeu_pd(out + k, _mm256_mul_pd(_mm256_sub_pd(_mm256_loadu_pd(column + k), c),
                                              _mm256_loadu_pd(scale + k)));
    }
    for (; k < n; ++k) out[k] = (column[k] - centre[i]) * scale[k];
  }
}

void subtract_product(const double* h, long n, long p, long ldh, const double* theta, double* e) {
  for (long i = 0; i < p; ++i) {
    const double* column = h + i * ldh;
    const __m256d t = _mm256_set1_pd(theta[i]);
    long k = 0;
    for (; k + kLanes <= n; k += kLanes) {
      // The same column's next n rows, which the sweep's next chunk reads: a chunk's column of
      // 512 doubles is one 4 KB page, where the hardware's prefetcher stops, so each column of
      // each chunk otherwise starts from main memory (at p = 17 this product was the sweep's
      // largest cost, for p multiply-adds a range). A prefetch never faults: past the matrix's
      // last row it only costs a line.
      if (k % kDoublesPerLine == 0) {
        _mm_prefetch(reinterpret_cast<const char*>(column + n + k), _MM_HINT_T1);
      }
      _mm256_storeu_pd(e + k,
                       _mm256_fnmadd_pd(_mm256_loadu_pd(column + k), t, _mm256_loadu_pd(e + k)));
    }
    for (; k < n; ++k) e[k] -= column[k] * theta[i];
  }
}

}  // namespace tofcomp::core::avx2
