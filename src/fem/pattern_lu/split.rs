//! Two groups of independent subtrees of the supernodal elimination tree, for the two cores.
//!
//! A supernode's Schur update goes only to its ancestors (the supernodes that own the columns of
//! its off-diagonal rows), so disjoint subtrees can be eliminated at the same time. The tree is
//! cut from the root down: the frontier of subtrees starts at the roots and its heaviest subtree
//! (by the flops of its eliminations) is replaced by its children, its root joining the
//! supernodes left for after; at each cut the frontier is dealt into two groups, heaviest first
//! onto the lighter group. The cut kept is the one with the least estimated time, max(group) +
//! rest, in flops. Under the dissection order ([`crate::fem::dissection`]) the tree's top is
//! one separator over two halves of nearly equal flops, so the rest is 2–3 % of the flops
//! (27–34 % under the approximate minimum degree used before, whose top is a chain of
//! cross-sections).

/// Which supernodes are eliminated at the same time, and which after.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Split {
    /// The two groups, each a union of whole subtrees, supernodes ascending.
    pub groups: [Vec<usize>; 2],
    /// The supernodes left (the ancestors of the groups' subtrees), ascending.
    pub rest: Vec<usize>,
    /// Estimated speed-up over one core: all flops / (max(group flops) + rest flops).
    pub speedup: f64,
}

/// Cuts tried before the best is kept (each moves one supernode into the rest).
const CUTS: usize = 400;

impl Split {
    /// The best cut of the tree given by `parent` (None for a root; every parent is after its
    /// children) with the elimination flops of each supernode, or None if none gives both
    /// groups work.
    pub fn choose(parent: &[Option<usize>], flops: &[f64]) -> Option<Self> {
        let n = parent.len();
        let mut subtree = flops.to_vec();
        let mut children = vec![Vec::new(); n];
        for s in 0..n {
            if let Some(p) = parent[s] {
                subtree[p] += subtree[s];
                children[p].push(s);
            }
        }
        let total: f64 = flops.iter().sum();
        let mut frontier: Vec<usize> = (0..n).filter(|&s| parent[s].is_none()).collect();
        let mut rest_flops = 0.0;
        let mut best: Option<(f64, Vec<usize>)> = None;
        for _ in 0..CUTS {
            frontier.sort_by(|a, b| subtree[*b].total_cmp(&subtree[*a]));
            let mut load = [0.0; 2];
            for &t in &frontier {
                let g = usize::from(load[1] < load[0]);
                load[g] += subtree[t];
            }
            let time = load[0].max(load[1]) + rest_flops;
            if load[0] > 0.0 && load[1] > 0.0 && best.as_ref().is_none_or(|(b, _)| time < *b) {
                best = Some((time, frontier.clone()));
            }
            if frontier.is_empty() {
                break;
            }
            let top = frontier.remove(0);
            rest_flops += flops[top];
            frontier.extend(&children[top]);
        }
        let (time, roots) = best?;
        // Deal the kept frontier again and collect each group's subtrees.
        let mut group_of = vec![2u8; n];
        let mut load = [0.0; 2];
        for &t in &roots {
            let g = usize::from(load[1] < load[0]);
            load[g] += subtree[t];
            group_of[t] = g as u8;
        }
        // Every other supernode below a kept root is in its parent's group (parents come after
        // their children: walk from the highest index down).
        for s in (0..n).rev() {
            if let (2, Some(p)) = (group_of[s], parent[s]) {
                group_of[s] = group_of[p];
            }
        }
        let pick = |g: u8| (0..n).filter(|&s| group_of[s] == g).collect::<Vec<_>>();
        Some(Self {
            groups: [pick(0), pick(1)],
            rest: pick(2),
            speedup: total / time,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A root with two equal chains under it: the chains are the groups, the root the rest.
    #[test]
    fn two_equal_subtrees_go_to_the_two_groups() {
        // 0 → 1 → 4, 2 → 3 → 4.
        let parent = [Some(1), Some(4), Some(3), Some(4), None];
        let split = Split::choose(&parent, &[1.0, 1.0, 1.0, 1.0, 1.0]).unwrap();
        let mut groups = split.groups.clone();
        groups.sort();
        assert_eq!(groups, [vec![0, 1], vec![2, 3]]);
        assert_eq!(split.rest, vec![4]);
        assert!((split.speedup - 5.0 / 3.0).abs() < 1e-12);
    }

    /// A chain has no two independent subtrees.
    #[test]
    fn a_chain_cannot_be_split() {
        let parent = [Some(1), Some(2), None];
        assert_eq!(Split::choose(&parent, &[1.0; 3]), None);
    }
}
