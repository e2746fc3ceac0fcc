#include "python/errors.h"

#include <new>
#include <stdexcept>

#include "core/io/output_file.h"
#include "core/octree/octree.h"
#include "core/render/frame.h"
#include "core/scene/scene.h"
#include "core/system/resources.h"
#include "teach/teach_error.h"

namespace oct::python {
namespace {

// OSError(errno, message): Python picks the errno's subclass (ENOENT: FileNotFoundError).
void setOsError(int error, const char* message) {
    PyObject* args = Py_BuildValue("(is)", error, message);
    PyErr_SetObject(PyExc_OSError, args);
    Py_XDECREF(args);
}

}  // namespace

void registerErrorTranslator() {
    pybind11::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const SceneError& e) {
            if (e.osError() != 0)
                setOsError(e.osError(), e.what());
            else
                PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const ResourceError& e) {
            PyErr_SetString(PyExc_MemoryError, e.what());
        } catch (const OctreeError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const FrameError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const IoError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const TeachError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const std::invalid_argument& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const std::out_of_range& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
        // Anything else goes on to pybind11's own translator (std::bad_alloc: MemoryError,
        // std::exception: RuntimeError, pybind11's errors as themselves).
    });
}

}  // namespace oct::python
