//! Breadth-first searches over the nodes of a graph not yet ordered: level structures, the cut
//! of a piece by a thinned level, and the connected parts left.

use crate::fem::assembly::Pattern;

/// The searches of one dissection: which nodes are ordered, and the scratch of the last search.
pub(super) struct Search<'g> {
    graph: &'g Pattern,
    /// A node was reached by the last search when its stamp equals `current`.
    stamp: Vec<u32>,
    current: u32,
    /// The level of every node reached by the last search.
    level_of: Vec<u32>,
    /// The nodes already in the order (no search crosses them).
    pub ordered: Vec<bool>,
}

/// Breadth-first levels: level l is `nodes[ptr[l]..ptr[l + 1]]`.
pub(super) struct Levels {
    nodes: Vec<u32>,
    ptr: Vec<usize>,
}

impl Levels {
    pub fn depth(&self) -> usize {
        self.ptr.len() - 1
    }

    pub fn level(&self, l: usize) -> &[u32] {
        &self.nodes[self.ptr[l]..self.ptr[l + 1]]
    }

    /// The nodes of levels 0..=l.
    pub fn up_to(&self, l: usize) -> usize {
        self.ptr[l + 1]
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }
}

/// A separator and its cost |S| / (|A| |B|), A and B the nodes on either side.
struct Cut {
    separator: Vec<u32>,
    cost: f64,
}

impl<'g> Search<'g> {
    pub fn new(graph: &'g Pattern) -> Self {
        let n = graph.n;
        Self {
            graph,
            stamp: vec![0; n],
            current: 0,
            level_of: vec![0; n],
            ordered: vec![false; n],
        }
    }

    /// The neighbours of `v` (`v` itself included when the graph has its diagonal).
    pub fn neighbours(&self, v: u32) -> &'g [u32] {
        let g = self.graph;
        &g.row_idx[g.col_ptr[v as usize] as usize..g.col_ptr[v as usize + 1] as usize]
    }

    /// The neighbours of `v` not yet ordered, `v` excluded.
    fn free_neighbours(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.neighbours(v)
            .iter()
            .copied()
            .filter(move |&w| w != v && !self.ordered[w as usize])
    }

    /// The levels from `roots` (level 0) over the nodes not yet ordered.
    pub fn levels(&mut self, roots: &[u32]) -> Levels {
        self.current += 1;
        for &r in roots {
            self.stamp[r as usize] = self.current;
            self.level_of[r as usize] = 0;
        }
        let mut nodes = roots.to_vec();
        let mut ptr = vec![0, nodes.len()];
        while ptr[ptr.len() - 1] > ptr[ptr.len() - 2] {
            let level = (ptr.len() - 1) as u32;
            for k in ptr[ptr.len() - 2]..ptr[ptr.len() - 1] {
                for &w in self.neighbours(nodes[k]) {
                    let wi = w as usize;
                    if self.stamp[wi] != self.current && !self.ordered[wi] {
                        self.stamp[wi] = self.current;
                        self.level_of[wi] = level;
                        nodes.push(w);
                    }
                }
            }
            ptr.push(nodes.len());
        }
        ptr.pop();
        Levels { nodes, ptr }
    }

    /// Level l of the last search's `levels` thinned to its nodes with a neighbour in level
    /// l + 1: in a graph of element cliques a level is two rows of nodes, and only the row on
    /// the element boundary separates.
    pub fn thinned(&self, levels: &Levels, l: usize) -> Vec<u32> {
        let next = l as u32 + 1;
        levels
            .level(l)
            .iter()
            .copied()
            .filter(|&v| {
                self.free_neighbours(v).any(|w| {
                    self.stamp[w as usize] == self.current && self.level_of[w as usize] == next
                })
            })
            .collect()
    }

    /// A separator of the connected `piece`, or None if its level structures are too shallow
    /// to cut. The candidates are the best cut of the levels from a pseudo-peripheral node and
    /// those of the levels from either end of that cut's separator (from a square's corner the
    /// levels are L-shaped; from the middle of a side they end in straight lines).
    pub fn cut(&mut self, piece: &[u32]) -> Option<Vec<u32>> {
        let levels = self.peripheral_levels(piece[0]);
        let mut best = self.best_cut(&levels)?;
        let mut end = self.farthest(best.separator[0], &best.separator);
        for _ in 0..2 {
            let levels = self.levels(&[end]);
            let other = self.deepest(&best.separator);
            if let Some(cut) = self.best_cut(&levels).filter(|c| c.cost < best.cost) {
                best = cut;
            }
            end = other;
        }
        Some(best.separator)
    }

    /// The levels from a pseudo-peripheral node of the connected part holding `start`: from
    /// the last level's node of least degree, as long as the structure deepens (George and
    /// Liu's FNROOT). The last search is that of the levels returned.
    fn peripheral_levels(&mut self, start: u32) -> Levels {
        let mut levels = self.levels(&[start]);
        loop {
            let last = levels.level(levels.depth() - 1);
            let candidate = last
                .iter()
                .copied()
                .min_by_key(|&v| self.free_neighbours(v).count())
                .unwrap_or(start);
            let deeper = self.levels(&[candidate]);
            if deeper.depth() <= levels.depth() {
                return self.levels(&[levels.nodes[0]]);
            }
            levels = deeper;
        }
    }

    /// The node of `set` farthest from `root`.
    fn farthest(&mut self, root: u32, set: &[u32]) -> u32 {
        self.levels(&[root]);
        self.deepest(set)
    }

    /// The node of `set` in the deepest level of the last search.
    fn deepest(&self, set: &[u32]) -> u32 {
        set.iter()
            .copied()
            .max_by_key(|&v| self.level_of[v as usize])
            .unwrap_or(set[0])
    }

    /// The thinned level of the last search's `levels` with the least |S| / (|A| |B|), A the
    /// nodes before the separator (the level's other nodes included), B those after.
    fn best_cut(&self, levels: &Levels) -> Option<Cut> {
        let total = levels.len() as f64;
        let (cost, l) = (1..levels.depth().saturating_sub(1))
            .map(|l| {
                let s = self.thinned(levels, l).len() as f64;
                let before = levels.up_to(l) as f64 - s;
                let after = total - levels.up_to(l) as f64;
                (s / (before * after), l)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))?;
        Some(Cut {
            separator: self.thinned(levels, l),
            cost,
        })
    }

    /// The connected parts of the nodes of `piece` not yet ordered.
    pub fn components(&mut self, piece: &[u32]) -> Vec<Vec<u32>> {
        let mut parts = Vec::new();
        // The searches below stamp their parts from `first` on.
        let first = self.current + 1;
        for &v in piece {
            let stamp = self.stamp[v as usize];
            if !self.ordered[v as usize] && !(first..=self.current).contains(&stamp) {
                parts.push(self.levels(&[v]).nodes);
            }
        }
        parts
    }

    /// The nodes of `piece` with a neighbour already ordered.
    pub fn next_to_ordered(&self, piece: &[u32]) -> Vec<u32> {
        piece
            .iter()
            .copied()
            .filter(|&v| self.neighbours(v).iter().any(|&w| self.ordered[w as usize]))
            .collect()
    }
}
