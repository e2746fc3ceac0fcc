// numpy arrays in and out of the octrace module: the checks every argument passes (dtype,
// shape; a copy only when the layout is not C order) and results handed to Python without a
// copy (an owner object keeps the C++ buffer alive as the array's base).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

namespace oct::python {

namespace py = pybind11;

// "(3, 8) float64", as messages name what was given.
std::string describeArray(const py::array& a);
// A copy of `bytes` for argument `what` against the memory left (core/system/resources.h):
// MemoryError naming it when it does not fit.
void checkCopyMemory(const std::string& what, uint64_t bytes);

// `value` as a C-ordered array of dtype T (native byte order) whose dimensions after the first
// are one of `rowShapes` ({} for a 1-D array). A C-contiguous array is used in place; another
// layout of the same dtype is copied (the same values). Any other dtype or shape is a
// ValueError naming `what`, what was given and `expected`: values are never converted (a
// float64 ray rounded to float32 is not the ray the user traced).
template <class T>
py::array_t<T, py::array::c_style> checkedArray(const py::handle& value, const std::string& what,
                                                const std::vector<std::vector<ssize_t>>& rowShapes,
                                                const std::string& expected) {
    if (!py::isinstance<py::array>(value))
        throw py::type_error(what + " must be a numpy array (" + expected + "), not " +
                             std::string(py::str(py::type::of(value).attr("__name__"))));
    const py::array a = py::reinterpret_borrow<py::array>(value);
    bool shapeOk = false;
    for (const std::vector<ssize_t>& row : rowShapes) {
        if (a.ndim() != ssize_t(row.size()) + 1) continue;
        bool same = true;
        for (size_t k = 0; k < row.size(); ++k) same = same && a.shape(ssize_t(k) + 1) == row[k];
        shapeOk = shapeOk || same;
    }
    // equal, not is: a dtype that went through pickle (multiprocessing, joblib) is another
    // object of the same type; '>f4' is not equal to the native '<f4'.
    if (!a.dtype().equal(py::dtype::of<T>()) || !shapeOk)
        throw py::value_error(what + " must be " + expected + ", not " + describeArray(a));
    // ensure: the array itself when C-contiguous, else a C-ordered copy of the same dtype, sized
    // against the memory left first (a strided view of 2^40 rows over one row is cheap to make
    // and impossible to copy; pybind11's ensure swallows the MemoryError and returns null).
    if (!(a.flags() & py::array::c_style)) checkCopyMemory(what, uint64_t(a.size()) * sizeof(T));
    auto out = py::array_t<T, py::array::c_style>::ensure(a);
    if (!out) throw py::error_already_set();
    return out;
}

// Rows of `array` (its first dimension).
inline uint64_t rowsOf(const py::array& array) { return uint64_t(array.shape(0)); }

// A numpy array over `data`, moved into a heap owner the array keeps alive (no copy).
template <class T>
py::array_t<T> ownedArray(std::vector<T>&& data, const std::vector<ssize_t>& shape) {
    auto* owned = new std::vector<T>(std::move(data));
    py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return py::array_t<T>(shape, owned->data(), owner);
}

// A read-only numpy view of memory that `owner` (a Python object) keeps alive.
template <class T>
py::array_t<T> viewOf(const T* data, const std::vector<ssize_t>& shape, const py::handle& owner) {
    py::array_t<T> view(shape, data, owner);
    py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return view;
}

// Python's json.loads of a JSON text: the dicts the CLI's --json files hold, key for key.
py::object jsonToPython(const std::string& text);
// json.dumps of a Python object (dict, list), for C++ to parse.
std::string pythonToJson(const py::handle& value);

}  // namespace oct::python
