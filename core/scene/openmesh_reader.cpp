// OpenMesh's readers feeding RawMeshImporter, which records what they hand over without
// building a halfedge mesh (loader_detail.h says why and what the surveys add).
#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <iostream>
#include <mutex>
#include <new>
#include <sstream>
#include <utility>

#include "core/scene/loader_detail.h"

namespace oct::scene_detail {
namespace {

using OpenMesh::EdgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::VertexHandle;

// Readers call add_face and may then use the returned handle for per-face attributes, so a valid
// handle is returned and every attribute callback accepts any handle and does nothing.
class RawMeshImporter final : public OpenMesh::IO::BaseImporter {
public:
    RawMesh mesh;

    VertexHandle add_vertex(const OpenMesh::Vec3f& p) override { return push({p[0], p[1], p[2]}); }
    VertexHandle add_vertex(const OpenMesh::Vec3d& p) override {
        return push({float(p[0]), float(p[1]), float(p[2])});
    }
    VertexHandle add_vertex() override { return push({0.0f, 0.0f, 0.0f}); }
    void set_point(VertexHandle vh, const OpenMesh::Vec3f& p) override {
        if (vh.idx() >= 0 && size_t(vh.idx()) < mesh.vertices.size())
            mesh.vertices[size_t(vh.idx())] = {p[0], p[1], p[2]};
    }
    FaceHandle add_face(const VHandles& corners) override {
        for (VertexHandle vh : corners) mesh.faceIndices.push_back(vh.idx());
        mesh.faceStart.push_back(mesh.faceIndices.size());
        return FaceHandle(int(mesh.faceCount() - 1));
    }
    // Only OpenMesh's own .om reader builds faces from halfedges; .om is not dispatched here.
    FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
    HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }

    size_t n_vertices() const override { return mesh.vertices.size(); }
    size_t n_faces() const override { return mesh.faceCount(); }
    size_t n_edges() const override { return 0; }

    void add_face_texcoords(FaceHandle, VertexHandle,
                            const std::vector<OpenMesh::Vec2f>&) override {}
    void add_face_texcoords(FaceHandle, VertexHandle,
                            const std::vector<OpenMesh::Vec3f>&) override {}
    void set_face_texindex(FaceHandle, int) override {}
    void set_halfedge(VertexHandle, HalfedgeHandle) override {}
    void set_normal(VertexHandle, const OpenMesh::Vec3f&) override {}
    void set_normal(VertexHandle, const OpenMesh::Vec3d&) override {}
    void set_color(VertexHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(VertexHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(VertexHandle, const OpenMesh::Vec3f&) override {}
    void set_color(VertexHandle, const OpenMesh::Vec4f&) override {}
    void set_texcoord(VertexHandle, const OpenMesh::Vec2f&) override {}
    void set_status(VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void set_next(HalfedgeHandle, HalfedgeHandle) override {}
    void set_face(HalfedgeHandle, FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(HalfedgeHandle, const OpenMesh::Vec2f&) override {}
    void set_texcoord(VertexHandle, const OpenMesh::Vec3f&) override {}
    void set_texcoord(HalfedgeHandle, const OpenMesh::Vec3f&) override {}
    void set_status(HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void set_color(EdgeHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(EdgeHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(EdgeHandle, const OpenMesh::Vec3f&) override {}
    void set_color(EdgeHandle, const OpenMesh::Vec4f&) override {}
    void set_status(EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void set_normal(FaceHandle, const OpenMesh::Vec3f&) override {}
    void set_normal(FaceHandle, const OpenMesh::Vec3d&) override {}
    void set_color(FaceHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(FaceHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(FaceHandle, const OpenMesh::Vec3f&) override {}
    void set_color(FaceHandle, const OpenMesh::Vec4f&) override {}
    void set_status(FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void add_texture_information(int, std::string) override {}

private:
    VertexHandle push(Vec3 p) {
        mesh.vertices.push_back(p);
        return VertexHandle(int(mesh.vertices.size() - 1));
    }
};

// OpenMesh's readers talk on omerr()/omlog() (std::cerr/std::clog) and sometimes on std::cerr
// directly. During a read both go into a buffer, so a failure's reason ends up in our SceneError
// and nothing reaches the terminal as the only report of a problem.
class ReaderOutputCapture {
public:
    ReaderOutputCapture()
        : oldErr_(std::cerr.rdbuf(&buffer_)), oldLog_(std::clog.rdbuf(&buffer_)) {}
    ~ReaderOutputCapture() {
        flushOpenMeshStreams();
        std::cerr.rdbuf(oldErr_);
        std::clog.rdbuf(oldLog_);
    }
    ReaderOutputCapture(const ReaderOutputCapture&) = delete;
    ReaderOutputCapture& operator=(const ReaderOutputCapture&) = delete;

    // The captured messages on one line, at most 200 characters.
    std::string oneLine() {
        flushOpenMeshStreams();
        std::string text = buffer_.str();
        std::replace(text.begin(), text.end(), '\n', ' ');
        trimLine(text);
        return text.size() > 200 ? text.substr(0, 200) + "..." : text;
    }

private:
    static void flushOpenMeshStreams() {
        ::omerr().flush();
        ::omlog().flush();
    }
    std::stringbuf buffer_;  // declared first: the rdbuf swaps above point at it
    std::streambuf* oldErr_;
    std::streambuf* oldLog_;
};

// OpenMesh's readers are process-wide singletons with per-read state, and the capture above
// swaps process-wide stream buffers: one read at a time.
std::mutex& openMeshMutex() {
    static std::mutex mutex;
    return mutex;
}

// Runs read(importer, options) under the lock and the output capture; `path` and `format`
// name the file in a failure's SceneError.
template <class Read>
RawMesh readLocked(const std::string& path, const std::string& format, Read read) {
    std::lock_guard<std::mutex> lock(openMeshMutex());
    RawMeshImporter importer;
    ReaderOutputCapture capture;
    // Default options suffice: the PLY header and the STL file size select binary mode.
    OpenMesh::IO::Options options;
    bool ok = false;
    try {
        ok = read(importer, options);
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        throw SceneError("cannot read " + inQuotes(path) + " as " + format +
                         ": OpenMesh's reader threw '" + e.what() + "'; check the file");
    }
    if (!ok) {
        std::string why = capture.oneLine();
        throw SceneError("cannot read " + inQuotes(path) + " as " + format +
                         ": OpenMesh's reader failed" + (why.empty() ? "" : " (" + why + ")") +
                         "; check that it is a valid " + format + " file");
    }
    return std::move(importer.mesh);
}

}  // namespace

RawMesh readWithOpenMesh(const std::string& path, const std::string& format) {
    return readLocked(path, format, [&](RawMeshImporter& importer, OpenMesh::IO::Options& o) {
        return OpenMesh::IO::IOManager().read(path, importer, o);
    });
}

RawMesh readWithOpenMesh(std::istream& in, const std::string& extension, const std::string& path,
                         const std::string& format) {
    return readLocked(path, format, [&](RawMeshImporter& importer, OpenMesh::IO::Options& o) {
        return OpenMesh::IO::IOManager().read(in, extension, importer, o);
    });
}

}  // namespace oct::scene_detail
