//! The cells' mapped geometry, computed once per mesh and cached by the assembly
//! (`fem::element::PointGeometry`), against closed forms that do not depend on it: on a mesh
//! whose interior nodes are moved off the lattice (curved, non-affine cells), every quadrature
//! point must (a) carry the exact deformation gradient of a linear displacement field, which
//! isoparametric elements reproduce, and (b) the volume weights must add up to the cylinder's
//! volume π R² L, which the Gauss rules integrate exactly (Q2: r det J has degree ≤ 5 in each
//! reference coordinate, 3 points are exact to degree 5; Q1: degree ≤ 2, 2 points exact to 3).

use activemuscle::fem::assembly::Assembler;
use activemuscle::fem::dofs::DofMap;
use activemuscle::fem::{Bases, Boundary, Element, Mesh};

/// A deterministic pseudo-random number in [−1, 1].
fn wiggle(k: usize) -> f64 {
    ((k as f64 + 1.0) * 12.9898).sin() * 0.5 + ((k as f64 + 3.0) * 78.233).sin() * 0.5
}

/// The structured nr × nz mesh of [0, R] × [0, L] with every node off the boundary moved by up
/// to `amplitude` times the cell size in r and z.
fn distorted(element: Element, radius: f64, length: f64, amplitude: f64) -> Mesh {
    let (nr, nz) = (4, 6);
    let mut mesh = Mesh::structured(radius, length, nr, nz, 1.0)
        .unwrap()
        .with_element(element);
    let mut on_boundary = vec![false; mesh.n_nodes()];
    for tag in [
        Boundary::Axis,
        Boundary::Bottom,
        Boundary::Top,
        Boundary::Lateral,
    ] {
        for &a in mesh.boundary(tag) {
            on_boundary[a as usize] = true;
        }
    }
    let (hr, hz) = (radius / nr as f64, length / nz as f64);
    for (a, x) in mesh.nodes.iter_mut().enumerate() {
        if !on_boundary[a] {
            x[0] += amplitude * hr * wiggle(2 * a);
            x[1] += amplitude * hz * wiggle(2 * a + 1);
        }
    }
    mesh
}

#[test]
fn cached_geometry_reproduces_linear_fields_and_the_volume_on_a_distorted_mesh() {
    let (radius, length) = (1.3, 3.7);
    // u_r = a r + e z, u_z = b r + c z: F_rr = 1 + a, F_rz = e, F_zr = b, F_zz = 1 + c,
    // F_θθ = 1 + u_r / r = 1 + a + e z / r.
    let (a, e, b, c) = (0.11, -0.07, 0.05, 0.23);
    for element in Element::ALL {
        let mesh = distorted(element, radius, length, 0.2);
        let dofs = DofMap::new(&mesh, Bases::Clamped);
        let assembler = Assembler::new(&mesh, &dofs).unwrap();
        let mut x = vec![0.0; dofs.n_total];
        for (node, [gr, gz]) in mesh.nodes.iter().zip(&dofs.node_u) {
            let [r, z] = *node;
            x[*gr as usize] = a * r + e * z;
            x[*gz as usize] = b * r + c * z;
        }
        let points = assembler.quadrature_points(&x);
        assert_eq!(
            points.len(),
            mesh.n_elements() * element.quadrature_points()
        );
        let mut volume = 0.0;
        for q in &points {
            let exact = [1.0 + a, e, b, 1.0 + c, 1.0 + a + e * q.z / q.r];
            for (i, (f, g)) in q.f.iter().zip(exact).enumerate() {
                assert!(
                    (f - g).abs() < 1e-13,
                    "{element} cell {} point {}: F[{i}] = {f} vs exact {g}",
                    q.element,
                    q.point
                );
            }
            volume += q.dv;
        }
        let exact = std::f64::consts::PI * radius * radius * length;
        assert!(
            (volume - exact).abs() < 1e-13 * exact,
            "{element}: Σ dV = {volume} vs π R² L = {exact}"
        );
    }
}
