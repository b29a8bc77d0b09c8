#pragma once
// While a SerialOpenMp lives, the OpenMP regions its thread starts run on that thread alone, with
// no team: this library defines libgomp's entry for a parallel region (GOMP_parallel, the only one
// Debian's CHOLMOD calls), which the executable exports ahead of libgomp's. In a SerialOpenMp's
// scope a region's function is called directly (omp_get_num_threads() 1, omp_get_level() 0);
// elsewhere libgomp's own entry runs it. CHOLMOD's supernodal factorization opens a region of a
// fixed team of four per supernode, millions per run, and libgomp makes even a team of one per
// region. The max-active-levels ICV is set to 0 as well (per thread in libgomp), the thread's
// earlier value restored after. docs/DECISIONS.md: "CHOLMOD's loops on the solving thread" and
// "CHOLMOD's loops with no team at all".

namespace hydra_multi {

class SerialOpenMp {
 public:
  SerialOpenMp();
  ~SerialOpenMp();
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;

 private:
  int saved_;
};

}  // namespace hydra_multi
