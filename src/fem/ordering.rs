//! The elimination order of the tangent's dofs, shared by the LDLᵀ ([`super::ldlt`]) and the
//! pattern LU ([`super::pattern_lu`]): a dissection order of the node graph
//! ([`super::dissection`]: one separator between two halves for the two cores, the halves cut
//! into slabs, the rest by nested dissection and minimum degree), each node's displacement dofs
//! before its pressure dof, and a pressure without a node of its own (a Q1/P0 cell's) right
//! after the last of its cell's nodes, so that no pressure pivot is the zero diagonal of the
//! saddle point but a Schur complement.
//!
//! Against approximate minimum degree on the node graph (the order before), clamped cylinder
//! R = 1, L = 4, Q2/Q1: the LDLᵀ's values 640 711 against 621 134 (16 × 64 cells), 3.39 M
//! against 3.28 M (32 × 128), 16.96 M against 16.48 M (64 × 256); the LU's flops 0.7–2 % more,
//! the estimated two-core speed-up of the pattern LU's split 1.89–1.93 against 1.50–1.54.
//! Frozen explicit sweep (`examples/cylinder_sweep.rs`, alternated release runs, load < 2):
//! factorisation 6.06 → 4.86 ms per call at 9 360 dofs, 36.5 → 32.9 ms at 37 152, the same
//! Newton and GMRES iterations (BENCHMARKS.md, "The dissection order of the tangent").

use super::assembly::Pattern;
use super::dissection::nested_dissection;
use super::dofs::DofMap;
use super::mesh::Mesh;

/// Dofs without a node of their own (the pressure of a Q1/P0 cell): eliminated right after the
/// last, in the node ordering, of the node groups `after` (the cell's nodes), so that their
/// pivot is a Schur complement rather than the zero diagonal. At the end if `after` is empty.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Trailing {
    /// Node groups (indices into `node_dofs`) that must come first.
    pub after: Vec<u32>,
    /// The dofs.
    pub dofs: Vec<u32>,
}

/// The elimination order of the dofs: the dissection order of the node graph
/// `node_adjacency` ([`nested_dissection`]), each node's dofs `node_dofs[a]` in their order
/// (displacement, then pressure), and every [`Trailing`] group right after the last of its node
/// groups.
pub fn dof_ordering(
    node_dofs: &[Vec<u32>],
    node_adjacency: &Pattern,
    trailing: &[Trailing],
) -> Result<Vec<u32>, String> {
    let node_order = nested_dissection(node_adjacency)?;
    Ok(dofs_in_node_order(&node_order, node_dofs, trailing))
}

/// The dofs in the node order `node_order` (`node_order[k]`: the k-th node group), each
/// group's dofs `node_dofs[a]` in their order and every [`Trailing`] group right after the last
/// of its node groups (at the end if it has none).
pub fn dofs_in_node_order(
    node_order: &[u32],
    node_dofs: &[Vec<u32>],
    trailing: &[Trailing],
) -> Vec<u32> {
    let nn = node_order.len();
    let mut position = vec![0usize; nn];
    for (k, &a) in node_order.iter().enumerate() {
        position[a as usize] = k;
    }
    let mut after_position: Vec<Vec<usize>> = vec![Vec::new(); nn + 1];
    for (t, tr) in trailing.iter().enumerate() {
        let last = tr
            .after
            .iter()
            .map(|&a| position[a as usize])
            .max()
            .unwrap_or(nn);
        after_position[last].push(t);
    }
    let mut perm = Vec::new();
    for (k, &a) in node_order.iter().enumerate() {
        perm.extend_from_slice(&node_dofs[a as usize]);
        for &t in &after_position[k] {
            perm.extend_from_slice(&trailing[t].dofs);
        }
    }
    for &t in &after_position[nn] {
        perm.extend_from_slice(&trailing[t].dofs);
    }
    perm
}

/// Dof groups for the LDLᵀ ordering and their adjacency graph. One group per node with free
/// displacement dofs: those dofs, then the node's pressure dof (Q2/Q1). A pressure dof whose node
/// has no free displacement (e.g. on a clamped base) would be a zero pivot if eliminated first,
/// so it joins the group of a neighbouring node (sharing an element) and is eliminated after that
/// node's displacement dofs, which couple to it. A Q1/P0 cell pressure is eliminated right after
/// the last of its cell's node groups (the third return value). Dofs are given in the system's
/// numbering `index` (free dof → system index, `u32::MAX` if condensed out); a node without
/// system dofs (a condensed centre node) has no group.
pub fn node_structure(
    mesh: &Mesh,
    dofs: &DofMap,
    index: &[u32],
) -> (Vec<Vec<u32>>, Pattern, Vec<Trailing>) {
    let (group_of, groups) = node_groups(mesh, dofs, index);
    let nf = dofs.n_free as u32;
    // The cell's own pressures, [`super::element::Element::pressures`] per cell.
    let per_cell = mesh.element.pressures();
    let trailing = dofs
        .element_p
        .chunks_exact(per_cell)
        .zip(mesh.elements())
        .filter_map(|(p, e)| {
            let free: Vec<u32> = p
                .iter()
                .filter(|&&p| p < nf)
                .map(|&p| index[p as usize])
                .collect();
            (!free.is_empty()).then(|| Trailing {
                after: e
                    .iter()
                    .map(|&a| group_of[a as usize])
                    .filter(|&g| g != u32::MAX)
                    .collect(),
                dofs: free,
            })
        })
        .collect();
    let adjacency = group_adjacency(mesh, &group_of, groups.len());
    (groups, adjacency, trailing)
}

/// The group of every node (`u32::MAX`: none) and the free dofs of every group (see
/// [`node_structure`]).
fn node_groups(mesh: &Mesh, dofs: &DofMap, index: &[u32]) -> (Vec<u32>, Vec<Vec<u32>>) {
    let nf = dofs.n_free as u32;
    let nn_all = mesh.n_nodes();
    let mut group_of = vec![u32::MAX; nn_all];
    let mut groups: Vec<Vec<u32>> = Vec::new();
    // A condensed centre node keeps its (empty) group: the ordering sees the graph of the
    // uncondensed mesh (under minimum degree, at 148k dofs the factor of the graph without the
    // centre nodes was 22 % larger).
    let mut has_u = Vec::new();
    for (a, g) in group_of.iter_mut().enumerate() {
        let free: Vec<u32> = dofs.node_u[a].iter().copied().filter(|&g| g < nf).collect();
        if !free.is_empty() {
            let d: Vec<u32> = free
                .iter()
                .map(|&g| index[g as usize])
                .filter(|&s| s != u32::MAX)
                .collect();
            *g = groups.len() as u32;
            has_u.push(!d.is_empty());
            groups.push(d);
        }
    }
    // Node neighbours through elements.
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); nn_all];
    for e in mesh.elements() {
        for &a in e {
            neighbours[a as usize].extend(e.iter().copied().filter(|&b| b != a));
        }
    }
    let mut orphans = Vec::new();
    for a in 0..nn_all {
        let p = dofs.node_p[a];
        if p >= nf {
            continue;
        }
        let host = if group_of[a] != u32::MAX {
            Some(group_of[a])
        } else {
            neighbours[a]
                .iter()
                .map(|&b| group_of[b as usize])
                .find(|&g| g != u32::MAX && has_u[g as usize])
        };
        let p = index[p as usize];
        match host {
            Some(g) => groups[g as usize].push(p),
            None => orphans.push(p),
        }
    }
    if !orphans.is_empty() {
        // No displacement dof anywhere near (degenerate mesh): keep them, the LU will cope.
        groups.push(orphans);
    }
    (group_of, groups)
}

/// The graph of `ng` groups: two groups are adjacent when their nodes share an element.
fn group_adjacency(mesh: &Mesh, group_of: &[u32], ng: usize) -> Pattern {
    let mut cols: Vec<Vec<u32>> = vec![Vec::new(); ng];
    for e in mesh.elements() {
        for &a in e {
            let ga = group_of[a as usize];
            if ga == u32::MAX {
                continue;
            }
            for &b in e {
                let gb = group_of[b as usize];
                if gb != u32::MAX {
                    cols[ga as usize].push(gb);
                }
            }
        }
    }
    let mut col_ptr = vec![0u32];
    let mut row_idx = Vec::new();
    for (j, c) in cols.iter_mut().enumerate() {
        c.push(j as u32);
        c.sort_unstable();
        c.dedup();
        row_idx.extend_from_slice(c);
        col_ptr.push(row_idx.len() as u32);
    }
    Pattern {
        n: ng,
        col_ptr,
        row_idx,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::assembly::Assembler;
    use crate::fem::dofs::Bases;
    use crate::fem::element::Element;

    /// On the clamped cylinder with either element: the order is a permutation of the system's
    /// dofs; every node group is eliminated in one piece, its displacements before its
    /// pressures (its own and those of clamped neighbours); a cell pressure of Q1/P0 comes
    /// after every dof of its cell's node groups, next to them (only other cell pressures
    /// between).
    #[test]
    fn every_dof_once_each_node_in_one_piece_and_pressures_after_their_displacements() {
        for element in Element::ALL {
            let mesh = Mesh::structured(1.0, 4.0, 6, 24, 1.0)
                .unwrap()
                .with_element(element);
            let dofs = DofMap::new(&mesh, Bases::Clamped);
            let asm = Assembler::new(&mesh, &dofs).unwrap();
            let (groups, adjacency, trailing) = node_structure(&mesh, &dofs, asm.system_index());
            let perm = dof_ordering(&groups, &adjacency, &trailing).unwrap();
            let n = asm.pattern.n;
            let mut position = vec![usize::MAX; n];
            for (k, &i) in perm.iter().enumerate() {
                assert_eq!(position[i as usize], usize::MAX, "{element}: dof {i} twice");
                position[i as usize] = k;
            }
            assert!(position.iter().all(|&k| k < n), "{element}: a dof missing");
            let mut pressure = vec![false; n];
            for &p in dofs.node_p.iter().filter(|&&p| p < dofs.n_free as u32) {
                pressure[asm.system_index()[p as usize] as usize] = true;
            }
            let mut group_of_position = vec![None; n];
            for (g, group) in groups.iter().enumerate() {
                for (k, &i) in group.iter().enumerate() {
                    assert_eq!(position[i as usize], position[group[0] as usize] + k);
                    let displacement_after = group[k..].iter().any(|&j| !pressure[j as usize]);
                    assert!(
                        !pressure[i as usize] || !displacement_after,
                        "{element}: {g}"
                    );
                    group_of_position[position[i as usize]] = Some(g as u32);
                }
            }
            assert_eq!(trailing.is_empty(), element == Element::Q2Q1);
            for t in &trailing {
                let first = position[t.dofs[0] as usize];
                let before = (0..first).rev().find_map(|k| group_of_position[k]);
                assert!(before.is_some_and(|g| t.after.contains(&g)), "{element}");
                for &g in &t.after {
                    assert!(groups[g as usize]
                        .iter()
                        .all(|&i| position[i as usize] < first));
                }
            }
        }
    }
}
