// The deformation on the GPU (renderer.h): the cage and its box layers uploaded as buffer textures, the mesh's
// rest positions and cells once, each vertex deformed in shaders/mesh.vert (Hu et al. 2001, eq. 1 evaluated
// per vertex), and the transform-feedback capture that tests compare with the CPU path.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "render/overlay_geometry.h"
#include "render/renderer.h"
#include "render/renderer_state.h"
#include "render/shader_program.h"

namespace sculpt::render {

// ---- the deformation on the GPU ------------------------------------------------------------------

std::string Renderer::gpuDeformationProblem(const core::Lattice& cage, const std::vector<const core::Lattice*>& layers) {
    if (cage.volume)
        return "a " + cage.volume->kindName() + " lattice is deformed on the CPU (the GPU path takes box lattices)";
    if (cage.controlPointCount() <= 0) return "there is no lattice";
    if (int(layers.size()) > kMaxGpuLayers)
        return std::to_string(layers.size()) + " layers are deformed on the CPU (the GPU path takes up to " +
               std::to_string(kMaxGpuLayers) + ")";
    for (const core::Lattice* layer : layers)
        if (!layer || layer->volume || layer->controlPointCount() <= 0)
            return "a layer that is not a box lattice is deformed on the CPU";
    return {};
}

namespace {

// Checks one lattice's arrays for the GPU path (sizes, finite values); `what` names it in the message.
Status checkGpuLatticeValues(const core::Lattice& lattice, const std::string& what) {
    const Eigen::Index points = lattice.controlPointCount();
    if (lattice.displacement.rows() != points || Eigen::Index(lattice.weights.size()) != points)
        return Status::error("GPU deformation: " + what + " has " + std::to_string(points) + " control points but " +
                             std::to_string(lattice.displacement.rows()) + " displacements and " +
                             std::to_string(lattice.weights.size()) + " weights");
    for (Eigen::Index i = 0; i < points; ++i) {
        if (!lattice.displacement.row(i).allFinite())
            return Status::error("GPU deformation: the displacement of control point " + lattice.controlPointName(int(i)) +
                                 " of " + what + " is not finite");
        if (!(lattice.weights[size_t(i)] > 0.0) || !std::isfinite(lattice.weights[size_t(i)]))
            return Status::error("GPU deformation: the weight of control point " + lattice.controlPointName(int(i)) +
                                 " of " + what + " is not a finite positive number");
    }
    if (!lattice.boxMin.allFinite() || !lattice.boxMax.allFinite() || !((lattice.boxMax - lattice.boxMin).array() > 0.0).all())
        return Status::error("GPU deformation: the box of " + what + " is empty or not finite");
    return Status::success();
}

// The kinds first, then every lattice's values.
Status checkGpuLattices(const core::Lattice& cage, const std::vector<const core::Lattice*>& layers) {
    if (std::string problem = Renderer::gpuDeformationProblem(cage, layers); !problem.empty())
        return Status::error("GPU deformation: " + problem);
    if (Status status = checkGpuLatticeValues(cage, "the lattice"); !status) return status;
    for (size_t k = 0; k < layers.size(); ++k)
        if (Status status = checkGpuLatticeValues(*layers[k], "layer " + std::to_string(k + 1)); !status) return status;
    return Status::success();
}

GpuLatticeShape shapeOf(const core::Lattice& lattice) {
    GpuLatticeShape shape;
    shape.count = lattice.count;
    shape.degree = lattice.degree;
    shape.spans = lattice.spans();
    shape.boxMin = lattice.boxMin;
    shape.boxMax = lattice.boxMax;
    return shape;
}

}  // namespace

void Renderer::State::uploadLattices(const core::Lattice& cage, const std::vector<const core::Lattice*>& layers) {
    std::vector<const core::Lattice*> all{&cage};
    all.insert(all.end(), layers.begin(), layers.end());
    // The table first (mesh.vert), then each lattice's bases: each axis's span polynomials and first functions.
    std::vector<float> basis(all.size() * kLatticeTableStride, 0.0f);
    std::vector<int> controlOffset(all.size() + 1, 0);
    for (size_t l = 0; l < all.size(); ++l) {
        const core::Lattice& source = *all[l];
        const GpuLatticeShape shape = shapeOf(source);
        const size_t row = l * kLatticeTableStride;
        // The GPU frame's origin in the box's coordinates (itself for an unturned box).
        const Eigen::Vector3d turnedOrigin = core::toBoxCoordinates(source, Eigen::Vector3d(frame.origin[0], frame.origin[1], frame.origin[2]));
        for (int a = 0; a < 3; ++a) {
            const core::SplineAxis& axis = source.axes[size_t(a)];
            basis[row + 9 + size_t(a)] = float(basis.size());
            for (double c : axis.coefficients) basis.push_back(float(c));
            basis[row + 12 + size_t(a)] = float(basis.size());
            for (int span = 0; span < axis.spans; ++span) basis.push_back(float(axis.first(span)));
            basis[row + size_t(a)] = float(shape.count[size_t(a)]);
            basis[row + 3 + size_t(a)] = float(shape.degree[size_t(a)]);
            basis[row + 6 + size_t(a)] = float(shape.spans[size_t(a)]);
            // The box in the GPU frame, and the local coordinate per unit there: spans over the box's size. A
            // turned box (a brush stroke's, core/volume/lattice.h): its corner in box coordinates relative to the turned
            // origin, (boxMin - A origin) / scale, and A's rows at 22-30, so t = (A p - corner) * perUnit.
            basis[row + 16 + size_t(a)] = float((shape.boxMin[a] - turnedOrigin[a]) / frame.scale);
            for (int c = 0; c < 3; ++c) basis[row + 22 + size_t(3 * a + c)] = float(source.boxAxes(a, c));
            basis[row + 19 + size_t(a)] =
                float(double(shape.spans[size_t(a)]) * frame.scale / (shape.boxMax[a] - shape.boxMin[a]));
        }
        basis[row + 15] = float(controlOffset[l]);
        controlOffset[l + 1] = controlOffset[l] + source.controlPointCount();
    }
    gpuCage = shapeOf(cage);
    gpuLatticeCount = int(all.size());
    const int controlCount = controlOffset.back();
    std::vector<float> control(size_t(controlCount) * 4);
    const double inverseScale = 1.0 / frame.scale;  // displacements are differences: no origin
    for (size_t l = 0; l < all.size(); ++l) {
        const core::Lattice& source = *all[l];
        float* out = control.data() + size_t(controlOffset[l]) * 4;
        for (int i = 0; i < source.controlPointCount(); ++i) {
            for (int c = 0; c < 3; ++c) out[size_t(i) * 4 + size_t(c)] = float(source.displacement(i, c) * inverseScale);
            out[size_t(i) * 4 + 3] = float(source.weights[size_t(i)]);
        }
    }
    // Only what changed goes up: during a drag, the one lattice being solved (many layers stay as they are).
    gl.BindBuffer(GL_TEXTURE_BUFFER, controlBuffer);
    if (control.size() != controlData.size()) {
        gl.BufferData(GL_TEXTURE_BUFFER, GLsizeiptr(control.size() * sizeof(float)), control.data(), GL_STREAM_DRAW);
        lastUpload.controlPointsUploaded = controlCount;
    } else {
        const auto first = std::mismatch(control.begin(), control.end(), controlData.begin()).first - control.begin();
        if (first < std::ptrdiff_t(control.size())) {
            std::ptrdiff_t last = std::ptrdiff_t(control.size());
            while (control[size_t(last - 1)] == controlData[size_t(last - 1)]) --last;
            const std::ptrdiff_t from = first / 4 * 4, to = (last + 3) / 4 * 4;  // whole control points
            gl.BufferSubData(GL_TEXTURE_BUFFER, GLintptr(from) * GLintptr(sizeof(float)), GLsizeiptr(to - from) * GLsizeiptr(sizeof(float)),
                             control.data() + from);
            lastUpload.controlPointsUploaded = int((to - from) / 4);
        }
    }
    controlData = std::move(control);
    if (basis != basisData) {  // a layer came or went: the table and bases go up too
        basisData = std::move(basis);
        gl.BindBuffer(GL_TEXTURE_BUFFER, basisBuffer);
        gl.BufferData(GL_TEXTURE_BUFFER, GLsizeiptr(basisData.size() * sizeof(float)), basisData.data(), GL_STATIC_DRAW);
    }
    gl.BindBuffer(GL_TEXTURE_BUFFER, 0);
}

Status Renderer::setGpuDeformation(const core::Lattice& lattice, const core::Embedding& embedding, const Positions& rest,
                                   const std::vector<const core::Lattice*>& layers) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    const int vertexCount = int(s.positions.rows());
    if (vertexCount == 0) return Status::error("GPU deformation: there is no mesh");
    if (rest.rows() != vertexCount || embedding.vertexCount != vertexCount)
        return Status::error("GPU deformation: " + std::to_string(rest.rows()) + " rest positions and an embedding of " +
                             std::to_string(embedding.vertexCount) + " vertices for a mesh of " +
                             std::to_string(vertexCount) + " vertices");
    if (Status status = checkFinite(rest, "rest position"); !status) return status;
    if (Status status = checkGpuLattices(lattice, layers); !status) return status;
    const std::array<int, 3> spans = lattice.spans();
    const int cellCount = spans[0] * spans[1] * spans[2];
    if (int(embedding.cellStart.size()) != cellCount + 1 || embedding.localX.size() != embedding.order.size())
        return Status::error("GPU deformation: the embedding was made for another lattice (" +
                             std::to_string(int(embedding.cellStart.size()) - 1) + " cells, the lattice has " +
                             std::to_string(cellCount) + ")");
    if (embedding.collarCount() > 0)
        return Status::error("GPU deformation: " + std::to_string(embedding.collarCount()) +
                             " vertices rest outside the lattice's box, which its collar carries (the CPU path evaluates it)");

    // Per vertex: local coordinates in its cell and the cell, or the identity's mark -1 outside the box.
    std::vector<float> cells(size_t(vertexCount) * 4, 0.0f);
    for (int v = 0; v < vertexCount; ++v) cells[size_t(v) * 4 + 3] = -1.0f;
#pragma omp parallel for schedule(dynamic, 64) if (cellCount > 64)
    for (int cell = 0; cell < cellCount; ++cell)
        for (int e = embedding.cellStart[size_t(cell)]; e < embedding.cellStart[size_t(cell) + 1]; ++e) {
            float* record = cells.data() + size_t(embedding.order[size_t(e)]) * 4;
            record[0] = float(embedding.localX[size_t(e)]);
            record[1] = float(embedding.localY[size_t(e)]);
            record[2] = float(embedding.localZ[size_t(e)]);
            record[3] = float(cell);
        }
    Positions restNormals;
    core::computeVertexNormals(rest, s.triangles, s.adjacency, restNormals);

    const GlFunctions& gl = s.gl;
    s.packVertices(0, vertexCount, rest, restNormals);
    gl.BindBuffer(GL_ARRAY_BUFFER, s.vertexBuffer);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(s.staging.size() * sizeof(float)), s.staging.data(), GL_DYNAMIC_DRAW);
    gl.BindBuffer(GL_ARRAY_BUFFER, s.cellBuffer);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(cells.size() * sizeof(float)), cells.data(), GL_STATIC_DRAW);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    gl.BindVertexArray(s.meshVao);
    gl.EnableVertexAttribArray(kAttribLatticeCell);
    gl.BindVertexArray(0);
    s.basisData.clear();
    s.controlData.clear();
    s.uploadLattices(lattice, layers);  // the buffers' stores exist before the textures are attached to them
    gl.BindTexture(GL_TEXTURE_BUFFER, s.basisTexture);
    gl.TexBuffer(GL_TEXTURE_BUFFER, GL_R32F, s.basisBuffer);
    gl.BindTexture(GL_TEXTURE_BUFFER, s.controlTexture);
    gl.TexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, s.controlBuffer);
    gl.BindTexture(GL_TEXTURE_BUFFER, 0);
    s.gpuDeformation = true;
    s.lastUpload = {vertexCount, 1, true, s.lastUpload.controlPointsUploaded};
    s.staging.clear();
    s.staging.shrink_to_fit();
    return Status::success();
}

Status Renderer::updateGpuDeformation(const core::Lattice& lattice, const std::vector<const core::Lattice*>& layers) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    if (!s.gpuDeformation) return Status::error("GPU deformation: the GPU path is off (setGpuDeformation first)");
    if (Status status = checkGpuLattices(lattice, layers); !status) return status;
    if (!shapeOf(lattice).sameLattice(s.gpuCage))
        return Status::error("GPU deformation: the lattice is not the one the GPU path was set up with (other counts, "
                             "degrees or box); set it up again");
    s.lastUpload = {};
    s.uploadLattices(lattice, layers);
    return Status::success();
}

Status Renderer::clearGpuDeformation(const Positions& positions) {
    State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    if (positions.rows() != s.positions.rows())
        return Status::error("clearGpuDeformation: " + std::to_string(positions.rows()) + " positions given for a mesh of " +
                             std::to_string(s.positions.rows()) + " vertices");
    if (!s.gpuDeformation) return Status::success();
    if (Status status = checkFinite(positions, "mesh position"); !status) return status;
    s.positions = positions;
    s.uploadAllVertices();
    s.gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    s.leaveGpuPath();
    return Status::success();
}

void Renderer::State::leaveGpuPath() {
    gl.BindVertexArray(meshVao);
    gl.DisableVertexAttribArray(kAttribLatticeCell);
    gl.BindVertexArray(0);
    gpuDeformation = false;
}

bool Renderer::gpuDeformationActive() const { return state_->gpuDeformation; }

void Renderer::State::bindGpuDeformation() const {
    gl.Uniform1i(deformUniforms.control, 0);
    gl.Uniform1i(deformUniforms.basis, 1);
    gl.Uniform1i(deformUniforms.latticeCount, gpuLatticeCount);
    gl.ActiveTexture(GL_TEXTURE1);
    gl.BindTexture(GL_TEXTURE_BUFFER, basisTexture);
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_BUFFER, controlTexture);
}

void Renderer::State::unbindGpuDeformation() const {
    gl.ActiveTexture(GL_TEXTURE1);
    gl.BindTexture(GL_TEXTURE_BUFFER, 0);
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_BUFFER, 0);
}

Status Renderer::captureGpuDeformation(Positions& positions, Positions& normals) const {
    const State& s = *state_;
    if (!s.ready) return Status::error("renderer not initialised");
    if (!s.gpuDeformation) return Status::error("captureGpuDeformation: the GPU path is off");
    const GlFunctions& gl = s.gl;
    const int vertexCount = int(s.positions.rows());
    for (int i = 0; i < 32 && gl.GetError() != GL_NO_ERROR; ++i) {
    }
    GLuint feedback = 0;
    gl.GenBuffers(1, &feedback);
    gl.BindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, feedback);
    gl.BufferData(GL_TRANSFORM_FEEDBACK_BUFFER, GLsizeiptr(vertexCount) * kFeedbackFloats * GLsizeiptr(sizeof(float)),
                  nullptr, GL_STREAM_READ);
    gl.BindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, feedback);
    gl.UseProgram(s.deformProgram);
    s.bindGpuDeformation();
    gl.BindVertexArray(s.meshVao);
    gl.Enable(GL_RASTERIZER_DISCARD);
    gl.BeginTransformFeedback(GL_POINTS);
    gl.DrawArrays(GL_POINTS, 0, vertexCount);
    gl.EndTransformFeedback();
    gl.Disable(GL_RASTERIZER_DISCARD);
    std::vector<float> captured(size_t(vertexCount) * kFeedbackFloats);
    gl.GetBufferSubData(GL_TRANSFORM_FEEDBACK_BUFFER, 0, GLsizeiptr(captured.size() * sizeof(float)), captured.data());
    gl.BindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
    gl.BindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, 0);
    gl.DeleteBuffers(1, &feedback);
    gl.BindVertexArray(0);
    gl.UseProgram(0);
    s.unbindGpuDeformation();
    if (const GLenum error = gl.GetError(); error != GL_NO_ERROR)
        return Status::error("captureGpuDeformation failed: " + glErrorText(error));
    positions.resize(vertexCount, 3);
    normals.resize(vertexCount, 3);
    for (int v = 0; v < vertexCount; ++v) {
        const float* record = captured.data() + size_t(v) * kFeedbackFloats;
        Eigen::Vector3d normal(record[3], record[4], record[5]);
        if (normal.norm() > 0.0) normal.normalize();
        for (int c = 0; c < 3; ++c) positions(v, c) = double(record[c]) * s.frame.scale + s.frame.origin[c];
        normals.row(v) = normal.transpose();
    }
    return Status::success();
}
}  // namespace sculpt::render
