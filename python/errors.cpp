#include "python/errors.h"

#include <cstring>
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

// The message as a str: bytes of a file quoted in it that are not UTF-8 (a garbage line of a
// malformed scene) are kept as \x escapes instead of failing the decode and losing the message.
PyObject* messageText(const char* message) {
    return PyUnicode_DecodeUTF8(message, Py_ssize_t(std::strlen(message)), "backslashreplace");
}

void setError(PyObject* type, const char* message) {
    PyObject* text = messageText(message);
    PyErr_SetObject(type, text);
    Py_XDECREF(text);
}

}  // namespace

void setOsError(int error, const char* message) {
    // OSError(errno, message): Python picks the errno's subclass (ENOENT: FileNotFoundError).
    PyObject* args = Py_BuildValue("(iN)", error, messageText(message));
    PyErr_SetObject(PyExc_OSError, args);
    Py_XDECREF(args);
}

void registerErrorTranslator() {
    pybind11::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const SceneError& e) {
            if (e.osError() != 0)
                setOsError(e.osError(), e.what());
            else
                setError(PyExc_ValueError, e.what());
        } catch (const ResourceError& e) {
            setError(PyExc_MemoryError, e.what());
        } catch (const OctreeError& e) {
            setError(PyExc_ValueError, e.what());
        } catch (const FrameError& e) {
            setError(PyExc_ValueError, e.what());
        } catch (const IoError& e) {
            setError(PyExc_ValueError, e.what());
        } catch (const TeachError& e) {
            setError(PyExc_ValueError, e.what());
        } catch (const std::invalid_argument& e) {
            setError(PyExc_ValueError, e.what());
        } catch (const std::out_of_range& e) {
            setError(PyExc_ValueError, e.what());
        }
        // Anything else goes on to pybind11's own translator (std::bad_alloc: MemoryError,
        // std::exception: RuntimeError, pybind11's errors as themselves).
    });
}

}  // namespace oct::python
