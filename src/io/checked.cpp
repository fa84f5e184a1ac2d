#include "gimp/io/checked.hpp"

#include <cerrno>
#include <cstring>

namespace gimp {

std::string closeChecked(FILE *f) {
  errno = 0;
  int err = std::fflush(f) != 0 ? errno : 0;
  if (!err && std::ferror(f)) err = errno ? errno : EIO;
  if (std::fclose(f) != 0 && !err) err = errno ? errno : EIO;
  return err ? std::strerror(err) : "";
}

std::string frameGroup(PetscInt step) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "step_%08lld", static_cast<long long>(step));
  return buf;
}

QuietErrors::QuietErrors(bool petscErrors) {
  H5Eget_auto2(H5E_DEFAULT, &print_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  if (petscErrors) pushed_ = PetscPushErrorHandler(PetscReturnErrorHandler, nullptr) == 0;
}

QuietErrors::~QuietErrors() {
  if (pushed_) (void)PetscPopErrorHandler();
  H5Eset_auto2(H5E_DEFAULT, print_, data_);
}

} // namespace gimp
