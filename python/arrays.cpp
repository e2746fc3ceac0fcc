#include "python/arrays.h"

#include "core/system/resources.h"

namespace oct::python {

std::string describeArray(const py::array& a) {
    std::string shape = "(";
    for (ssize_t k = 0; k < a.ndim(); ++k) shape += (k ? ", " : "") + std::to_string(a.shape(k));
    if (a.ndim() == 1) shape += ",";
    return shape + ") " + std::string(py::str(a.dtype()));
}

void checkCopyMemory(const std::string& what, uint64_t bytes) {
    checkMemory(bytes, "a C-ordered copy of " + what,
                "pass a C-contiguous array (numpy.ascontiguousarray) of fewer rows");
}

py::object jsonToPython(const std::string& text) {
    return py::module_::import("json").attr("loads")(text);
}

std::string pythonToJson(const py::handle& value) {
    return py::str(py::module_::import("json").attr("dumps")(value));
}

}  // namespace oct::python
