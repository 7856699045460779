#include "subdivided_scan.h"

#include <vector>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/subdivision_method_3.h>

#include "../core/cgal_meshes.h"

namespace sculpt::bench {

bool loopSubdividedCgalMesh(const std::string& name, int iterations, Positions& positions, Triangles& triangles,
                            std::string& error) {
    if (!test::loadCgalMesh(name, positions, triangles, error)) return false;
    using Kernel = CGAL::Simple_cartesian<double>;
    using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
    Mesh mesh;
    std::vector<Mesh::Vertex_index> vertex;
    for (Eigen::Index v = 0; v < positions.rows(); ++v)
        vertex.push_back(mesh.add_vertex(Kernel::Point_3(positions(v, 0), positions(v, 1), positions(v, 2))));
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
        if (mesh.add_face(vertex[triangles(t, 0)], vertex[triangles(t, 1)], vertex[triangles(t, 2)]) == Mesh::null_face()) {
            error = name + ": triangle " + std::to_string(t) + " is not manifold, Loop subdivision needs a manifold";
            return false;
        }
    CGAL::Subdivision_method_3::Loop_subdivision(mesh, CGAL::parameters::number_of_iterations(iterations));
    mesh.collect_garbage();  // indices 0..n-1
    positions.resize(static_cast<Eigen::Index>(mesh.number_of_vertices()), 3);
    for (const auto v : mesh.vertices()) {
        const auto& p = mesh.point(v);
        positions.row(static_cast<Eigen::Index>(v.idx())) << p.x(), p.y(), p.z();
    }
    triangles.resize(static_cast<Eigen::Index>(mesh.number_of_faces()), 3);
    Eigen::Index row = 0;
    for (const auto f : mesh.faces()) {
        int k = 0;
        for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) triangles(row, k++) = static_cast<int>(v.idx());
        ++row;
    }
    return true;
}

}  // namespace sculpt::bench
