//! A dissection order of a graph, built for a factorisation on two cores: one separator cuts
//! the graph in two halves, eliminated at the same time, and is eliminated last. Graph-based
//! (no coordinates), for any mesh.
//!
//! 1. The graph is cut by George and Liu's automatic nested dissection (Computer Solution of
//!    Large Sparse Positive Definite Systems, 1981, ch. 8): the breadth-first levels from a
//!    pseudo-peripheral node, a level thinned to its nodes with a neighbour in the next level
//!    (in the graph of element cliques a level is two rows of nodes, of which only the row on
//!    the element boundary separates). The level kept minimises |S| / (|A| |B|), among the
//!    levels from that node and from either end of its separator ([`search`]).
//! 2. A half at least as long as wide (|H| ≥ |S|²) is cut into slabs by cross-sections: the
//!    levels from the separator, thinned, every slab of about [`SLAB`] |S|² nodes (George's
//!    one-way dissection). The slabs come first, then the cross-sections from the farthest to
//!    the nearest to the separator, so that each one's front is the next cross-section alone.
//!    On a long strip this is what minimum degree does (its cross-sections at every half
//!    width), but minimum degree eliminates its chain of cross-sections one after the other
//!    through the middle of the strip: 28–34 % of the flops after the two cores' subtrees.
//! 3. Every other piece is cut as in 1 until it has at most [`LEAF`] nodes, then ordered by
//!    minimum degree with its halo ([`minimum_degree`]).
//!
//! Separators come after the pieces they separate, so every piece is a contiguous range of the
//! order. Measured on the clamped cylinder's tangents (R = 1, L = 4), against minimum degree on
//! the whole node graph (the order before): LU flops Σ 2w³/3 + 2w²r + 2r²w over supernodes, and
//! the estimated two-core speed-up of [`super::pattern_lu`]'s split.
//!
//! | cells, element   | flops, minimum degree | flops, this order | speed-up | speed-up |
//! |------------------|-----------------------|-------------------|----------|----------|
//! | 16 × 64, Q2/Q1   | 1.018e8               | 1.025e8           | 1.50     | 1.93     |
//! | 32 × 128, Q2/Q1  | 8.92e8                | 9.03e8            | 1.52     | 1.89     |
//! | 64 × 256, Q2/Q1  | 7.58e9                | 7.73e9            | 1.54     | 1.90     |
//! | 16 × 64, Q1/P0   | 2.17e7                | 2.37e7            | 1.37     | 1.98     |
//! | 64 × 256, Q1/P0  | 1.92e9                | 2.20e9            | 1.55     | 1.99     |
//!
//! Plain nested dissection (3. everywhere) needed 22–24 % more flops than minimum degree on the
//! Q2/Q1 strips, an ideal one (cut at the middle of the longer side, by coordinates) 17–18 %:
//! on a strip, minimum degree's chain of cross-sections has smaller fronts than the nested
//! cross-sections. On a square mesh (32 × 32 cells) step 2 does not apply and the order needs
//! 13 % more flops than minimum degree, with a worse split (1.43 against 1.55).

mod minimum_degree;
mod search;

use super::assembly::Pattern;
use minimum_degree::halo_minimum_degree;
use search::Search;

/// Pieces of at most this many nodes are ordered by minimum degree, not cut (16 × 64 Q2/Q1,
/// while tuning: 1.023e8 flops with 16, 1.025e8 with 64).
const LEAF: usize = 64;

/// Nodes of a slab of step 2 per squared separator node: 0.2 puts a cross-section every 4
/// element rows of the Q2/Q1 strips (16 × 64 flops, while tuning: 1.08e8 with 0.15, 1.02e8
/// with 0.2, 1.10e8 with 0.25; 64 × 256: 8.1e9, 7.6e9, 7.7e9).
const SLAB: f64 = 0.2;

/// What is done with a piece.
#[derive(Clone, Copy)]
enum Stage {
    /// A connected part of the graph: cut in two halves.
    Whole,
    /// A half left by the cut of a whole part with a separator of `separator` nodes.
    Half { separator: usize },
    /// Cut until small.
    Nested,
}

/// The order of the nodes of `graph` (a symmetric pattern, the diagonal allowed): `order[k]`
/// is the node eliminated k-th.
pub fn nested_dissection(graph: &Pattern) -> Result<Vec<u32>, String> {
    let n = graph.n;
    let mut search = Search::new(graph);
    let mut order = Order {
        nodes: vec![0; n],
        next: n,
    };
    let all: Vec<u32> = (0..n as u32).collect();
    let mut pieces: Vec<(Vec<u32>, Stage)> = search
        .components(&all)
        .into_iter()
        .map(|p| (p, Stage::Whole))
        .collect();
    while let Some((piece, stage)) = pieces.pop() {
        let next = match stage {
            _ if piece.len() <= LEAF => None,
            Stage::Half { separator } if piece.len() >= separator * separator => {
                for section in cross_sections(&mut search, &piece) {
                    order.place(&mut search, &section);
                }
                Some(Stage::Nested)
            }
            Stage::Whole => search.cut(&piece).map(|separator| {
                order.place(&mut search, &separator);
                Stage::Half {
                    separator: separator.len(),
                }
            }),
            Stage::Half { .. } | Stage::Nested => search.cut(&piece).map(|separator| {
                order.place(&mut search, &separator);
                Stage::Nested
            }),
        };
        match next {
            Some(stage) => pieces.extend(search.components(&piece).into_iter().map(|p| (p, stage))),
            None => {
                let local = halo_minimum_degree(graph, &piece, &search.ordered)?;
                order.place(&mut search, &local);
            }
        }
    }
    Ok(order.nodes)
}

/// The order, filled from its end.
struct Order {
    nodes: Vec<u32>,
    /// The nodes placed so far fill `nodes[next..]`.
    next: usize,
}

impl Order {
    /// Puts `nodes`, in that order, just before the nodes already placed.
    fn place(&mut self, search: &mut Search<'_>, nodes: &[u32]) {
        self.next -= nodes.len();
        self.nodes[self.next..self.next + nodes.len()].copy_from_slice(nodes);
        for &v in nodes {
            search.ordered[v as usize] = true;
        }
    }
}

/// The cross-sections of step 2 in `piece`, nearest to the ordered nodes first: the levels
/// from the piece's nodes next to them, thinned, one every slab of about [`SLAB`] |S|² nodes
/// (no slab at the far end smaller than half that).
fn cross_sections(search: &mut Search<'_>, piece: &[u32]) -> Vec<Vec<u32>> {
    let roots = search.next_to_ordered(piece);
    if roots.is_empty() {
        return Vec::new();
    }
    let levels = search.levels(&roots);
    let mut sections = Vec::new();
    let mut slab = 0;
    for l in 0..levels.depth().saturating_sub(1) {
        slab += levels.level(l).len();
        let section = search.thinned(&levels, l);
        let target = SLAB * (section.len() * section.len()) as f64;
        let beyond = (levels.len() - levels.up_to(l)) as f64;
        if slab as f64 >= target && beyond >= 0.5 * target {
            sections.push(section);
            slab = 0;
        }
    }
    sections
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The node graph of an nr × nz mesh of 9-node cells (every cell a clique), the nodes on a
    /// (2 nr + 1) × (2 nz + 1) grid numbered row by row: node i + (2 nr + 1) j at (i, j).
    fn clique_grid(nr: usize, nz: usize) -> Pattern {
        let width = 2 * nr + 1;
        let n = width * (2 * nz + 1);
        let mut columns: Vec<Vec<u32>> = vec![Vec::new(); n];
        for (cj, ci) in (0..nz).flat_map(|cj| (0..nr).map(move |ci| (cj, ci))) {
            let cell: Vec<u32> = (0..3)
                .flat_map(|dj| (0..3).map(move |di| (2 * ci + di + width * (2 * cj + dj)) as u32))
                .collect();
            for &a in &cell {
                columns[a as usize].extend(&cell);
            }
        }
        let mut col_ptr = vec![0u32];
        let mut row_idx = Vec::new();
        for mut c in columns {
            c.sort_unstable();
            c.dedup();
            row_idx.extend(c);
            col_ptr.push(row_idx.len() as u32);
        }
        Pattern {
            n,
            col_ptr,
            row_idx,
        }
    }

    /// Two graphs side by side: one pattern with the nodes of `b` after those of `a`.
    fn side_by_side(a: &Pattern, b: &Pattern) -> Pattern {
        let shift = a.row_idx.len() as u32;
        let mut col_ptr = a.col_ptr.clone();
        col_ptr.extend(b.col_ptr[1..].iter().map(|&p| p + shift));
        let mut row_idx = a.row_idx.clone();
        row_idx.extend(b.row_idx.iter().map(|&i| i + a.n as u32));
        Pattern {
            n: a.n + b.n,
            col_ptr,
            row_idx,
        }
    }

    #[test]
    fn the_order_is_a_permutation_of_every_node_of_every_part() {
        // Three parts: a strip long enough for every step, a small square, a lone node.
        let lone = Pattern {
            n: 1,
            col_ptr: vec![0, 1],
            row_idx: vec![0],
        };
        let graph = side_by_side(
            &side_by_side(&clique_grid(6, 40), &clique_grid(3, 3)),
            &lone,
        );
        let order = nested_dissection(&graph).unwrap();
        let mut seen = vec![false; graph.n];
        for &v in &order {
            assert!(!seen[v as usize], "node {v} twice");
            seen[v as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
    }

    /// On a strip of 16 × 64 cells the last nodes eliminated are the cross-section through the
    /// middle; every node below it is eliminated before every node above it (or after), so
    /// the two halves, joined by no edge, are two independent subtrees.
    #[test]
    fn the_last_separator_is_a_cross_section_between_two_halves() {
        let (nr, nz) = (16, 64);
        let width = 2 * nr + 1;
        let graph = clique_grid(nr, nz);
        let order = nested_dissection(&graph).unwrap();
        let row = |v: u32| v as usize / width;
        let separator = &order[order.len() - width..];
        let middle = row(separator[0]);
        assert!(separator.iter().all(|&v| row(v) == middle));
        assert_eq!(middle % 2, 0, "an element boundary");
        assert!(
            (nz - 8..=nz + 8).contains(&middle),
            "row {middle} of {}",
            2 * nz
        );
        let halves = &order[..order.len() - width];
        let first_is_below = row(halves[0]) < middle;
        let switch = halves
            .iter()
            .position(|&v| (row(v) < middle) != first_is_below)
            .unwrap();
        assert!(halves[switch..]
            .iter()
            .all(|&v| (row(v) < middle) != first_is_below));
        // No edge joins the two halves.
        let below = |v: u32| row(v) < middle;
        for &v in halves {
            for k in graph.col_ptr[v as usize]..graph.col_ptr[v as usize + 1] {
                let w = graph.row_idx[k as usize];
                assert!(row(w) == middle || below(w) == below(v), "{v}–{w}");
            }
        }
    }
}
