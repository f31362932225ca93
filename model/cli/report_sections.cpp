// The sections of `rayunits report`, in one place. Add a line per section; see
// model/include/rayunits/report/report.hpp for the contract. (Registrations live here, in a
// file linked straight into the executable, because the linker drops unreferenced objects
// of the static model library.)
#include "rayunits/report/accuracy.hpp"
#include "rayunits/report/report.hpp"

// id, title, order, function, needs_python, default_on
RU_REPORT_SECTION("accuracy", "Accuracy of add, mul, div and dot3 by exponent and fraction width", 100,
                  ru::report::accuracy_section, true, true);
