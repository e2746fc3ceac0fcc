// The interactive page of `octrace explain --html`: ONE self-contained HTML file (no server, no
// network) holding the scene's model, the cells the traversal touched coloured by visit order,
// the ray, its hit and its shadow ray, and the list of steps (the same lines as the text
// output). The script is three.js and teach/web/src/viewer.js, embedded in the binary
// (viewer_script.h), and the page's kernel: octrace's own kernel compiled to WebAssembly
// (page_kernel_script.h), which rebuilds the layout from the scene the page carries and
// explains any pixel a reader clicks. The data is one JSON object in the page.
#pragma once

#include <cstdint>
#include <string>

#include "core/scene/scene.h"
#include "teach/explain.h"
#include "teach/explain_page_data.h"

namespace oct {

// Models above these sizes are shown reduced, with a note on the page: triangle meshes by
// vertex clustering (Rossignac & Borrel 1993) to at most kPageMaxTriangles, point clouds by
// keeping every k-th point. The traced primitives themselves are always drawn exactly.
constexpr uint32_t kPageMaxTriangles = 120000;
constexpr uint32_t kPageMaxPoints = 200000;

struct PageStats {
    uint64_t modelPrimitives = 0;  // triangles or points drawn for the model
    bool reduced = false;          // the model was decimated or thinned
    uint64_t cells = 0;            // cells on the page
    uint64_t lines = 0;            // entries of the step list (headings excluded)
    uint64_t bytes = 0;            // the page's size
    bool kernel = false;           // the page traces pixels itself (its WebAssembly kernel)
    uint64_t kernelBytes = 0;      // the kernel's script (the WebAssembly module in base64)
};

// The page for explanation `e` of a pixel (or a ray) traced in `bs` with `options` and `frame`.
// With the page's kernel in this build (page_kernel_script.h) and a pixel explained, the page
// also carries the scene's primitives and the layout's build options (kernelSpec), rebuilds the
// same layout in WebAssembly, renders the image and explains any pixel clicked; otherwise it
// shows the recorded pixel and says why. Throws TeachError when this build has no viewer
// (configured with -DOCT_VIEWER=OFF).
std::string explainPage(const Explanation& e, const BuiltScene& bs, const LayoutOptions& options,
                        const FrameParams& frame, PageStats* stats = nullptr);

// A triangle mesh as indexed arrays, vertices shared where bit-identical; decimated by vertex
// clustering when it has more than maxTriangles. Exposed for tests.
struct IndexedMesh {
    std::vector<float> positions;   // x y z per vertex
    std::vector<uint32_t> indices;  // 3 per triangle
    bool decimated = false;
};
IndexedMesh pageMesh(const Scene& scene, uint32_t maxTriangles);

}  // namespace oct
