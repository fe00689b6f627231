// Reading and writing numbers in files must not depend on the caller's
// locale (a decimal comma would corrupt a mesh or a VTU file). uselocale()
// switches the calling thread only, so this is safe with other threads.
#pragma once
#include <locale.h>

namespace nd {

class ClassicNumericLocale {
 public:
  ClassicNumericLocale() : c_(newlocale(LC_NUMERIC_MASK, "C", static_cast<locale_t>(0))) {
    if (c_) previous_ = uselocale(c_);
  }
  ~ClassicNumericLocale() {
    if (c_) {
      uselocale(previous_);
      freelocale(c_);
    }
  }
  ClassicNumericLocale(const ClassicNumericLocale &) = delete;
  ClassicNumericLocale &operator=(const ClassicNumericLocale &) = delete;

 private:
  locale_t c_, previous_ = static_cast<locale_t>(0);
};

}  // namespace nd
