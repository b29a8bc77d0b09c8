#pragma once
// While a SerialOpenMp lives, the OpenMP regions its thread starts run on that thread alone: the
// max-active-levels ICV at 0 (per thread in libgomp), the thread's earlier value restored after.
// For libraries that open a fixed team per call, as CHOLMOD's supernodal factorization does (four
// threads to clear and assemble each supernode). It sets libgomp's ICV (linked as such, not
// through the compiler's OpenMP), the runtime Debian's CHOLMOD uses. docs/DECISIONS.md: "CHOLMOD's
// loops on the solving thread".

extern "C" {
void omp_set_max_active_levels(int max_levels);  // OpenMP's API, as libgomp exports it
int omp_get_max_active_levels(void);
}

namespace hydra_multi {

class SerialOpenMp {
 public:
  SerialOpenMp() : saved_(omp_get_max_active_levels()) { omp_set_max_active_levels(0); }
  ~SerialOpenMp() { omp_set_max_active_levels(saved_); }
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;

 private:
  int saved_;
};

}  // namespace hydra_multi
