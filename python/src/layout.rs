//! Where a point's entries live in a numpy array, without copying it.
//!
//! A batch is an array whose "component" axes (two for F and P, four for A, one for a fibre,
//! none for γ) sit either first — felupe's trailing-axes convention, F of shape (3, 3, q, c) — or
//! last, F of shape (..., 3, 3). The remaining "point" axes are read as one flat run of n points
//! when they flatten to a single stride, enumerated in C order (last point axis fastest) or in
//! Fortran order (first fastest); C- and F-contiguous arrays and their single-axis slices always
//! do. Any other array (a strided view in several axes) is copied once into that order.
//! Outputs are allocated in the input's order, so that point p is the same point everywhere.

use numpy::ndarray::ArrayViewD;

/// Where the component axes of a batch are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Convention {
    /// felupe's: components first, F of shape (3, 3, ...).
    Trailing,
    /// Components last, F of shape (..., 3, 3).
    Leading,
}

/// The order in which the points of a batch are enumerated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointOrder {
    /// Last point axis fastest.
    C,
    /// First point axis fastest.
    Fortran,
}

impl Convention {
    /// The positions of `components` component axes in an array of `ndim` axes.
    pub fn component_axes(self, ndim: usize, components: usize) -> std::ops::Range<usize> {
        match self {
            Convention::Trailing => 0..components,
            Convention::Leading => ndim - components..ndim,
        }
    }

    /// The full shape of an array with `components` (each of extent `extent`) around `points`.
    pub fn shape(self, points: &[usize], components: usize, extent: usize) -> Vec<usize> {
        let comps = std::iter::repeat_n(extent, components);
        match self {
            Convention::Trailing => comps.chain(points.iter().copied()).collect(),
            Convention::Leading => points.iter().copied().chain(comps).collect(),
        }
    }
}

/// Raw strided access to an array of f64: entry (p, c) at `ptr + p·point + Σ c_k·comp_k`
/// (strides in elements).
#[derive(Debug, Clone, Copy)]
pub struct Strided<const C: usize> {
    ptr: *mut f64,
    comp: [isize; C],
    point: isize,
}

// SAFETY: a `Strided` is only built over an array that outlives the computation (a borrowed
// numpy array held by its `PyReadonlyArray`, a copy owned by the `Input`, or an output array held
// by the caller), and concurrent writers touch disjoint points.
unsafe impl Send for Strided<0> {}
unsafe impl Sync for Strided<0> {}
unsafe impl Send for Strided<1> {}
unsafe impl Sync for Strided<1> {}
unsafe impl Send for Strided<2> {}
unsafe impl Sync for Strided<2> {}
unsafe impl Send for Strided<4> {}
unsafe impl Sync for Strided<4> {}

impl<const C: usize> Strided<C> {
    #[inline(always)]
    fn offset(&self, p: usize, c: [usize; C]) -> isize {
        let mut o = p as isize * self.point;
        for (ck, sk) in c.iter().zip(&self.comp) {
            o += *ck as isize * sk;
        }
        o
    }

    /// Entry (p, c).
    ///
    /// # Safety
    /// p < the number of points and c within the component extents of the array described.
    #[inline(always)]
    pub unsafe fn get(&self, p: usize, c: [usize; C]) -> f64 {
        *self.ptr.offset(self.offset(p, c))
    }

    /// Writes entry (p, c).
    ///
    /// # Safety
    /// As [`get`](Self::get), on a writable array that no other thread writes at point p.
    #[inline(always)]
    pub unsafe fn set(&self, p: usize, c: [usize; C], v: f64) {
        *self.ptr.offset(self.offset(p, c)) = v;
    }
}

/// The single stride of the point axes (`shape`, `strides` in elements) enumerated in `order`,
/// if they flatten to one; 0 when there is at most one point.
fn point_stride(shape: &[usize], strides: &[isize], order: PointOrder) -> Option<isize> {
    let mut axes: Vec<(usize, isize)> = shape
        .iter()
        .zip(strides)
        .filter(|(n, _)| **n != 1)
        .map(|(n, s)| (*n, *s))
        .collect();
    if order == PointOrder::Fortran {
        axes.reverse();
    }
    let Some(&(_, fastest)) = axes.last() else {
        return Some(0);
    };
    axes.windows(2)
        .all(|w| w[0].1 == w[1].1 * w[1].0 as isize)
        .then_some(fastest)
}

/// The `C` component axes of an array of `shape` and `strides` (elements), and the shape and
/// strides of its point axes.
fn split<const C: usize>(
    shape: &[usize],
    strides: &[isize],
    convention: Convention,
) -> (std::ops::Range<usize>, Vec<usize>, Vec<isize>) {
    let comps = convention.component_axes(shape.len(), C);
    let points = (0..shape.len()).filter(|a| !comps.contains(a));
    let point_shape = points.clone().map(|a| shape[a]).collect();
    let point_strides = points.map(|a| strides[a]).collect();
    (comps, point_shape, point_strides)
}

/// An input batch: its entries, borrowed in place, or copied once when its point axes do not
/// flatten in the order asked.
pub struct Input<const C: usize> {
    /// Access to the entries.
    pub strided: Strided<C>,
    /// The copy, when one was made (kept alive for `strided`).
    _copy: Option<Vec<f64>>,
}

/// Reads `view` (whose point axes are `points` points) with `C` component axes in `convention`;
/// `order` the enumeration wanted, or `None` for whichever the array allows (C tried first).
pub fn input<const C: usize>(
    view: &ArrayViewD<f64>,
    convention: Convention,
    order: Option<PointOrder>,
) -> (Input<C>, PointOrder) {
    let (comps, point_shape, point_strides) = split::<C>(view.shape(), view.strides(), convention);
    let comp: [isize; C] = std::array::from_fn(|k| view.strides()[comps.start + k]);
    let orders: &[PointOrder] = match order {
        Some(o) => &[o][..],
        None => &[PointOrder::C, PointOrder::Fortran],
    };
    for &o in orders {
        if let Some(point) = point_stride(&point_shape, &point_strides, o) {
            let strided = Strided {
                ptr: view.as_ptr() as *mut f64,
                comp,
                point,
            };
            return (
                Input {
                    strided,
                    _copy: None,
                },
                o,
            );
        }
    }
    // One copy, points outermost in the wanted order, components innermost (row-major).
    let order = order.unwrap_or(PointOrder::C);
    let mut axes: Vec<usize> = (0..view.ndim()).filter(|a| !comps.contains(a)).collect();
    if order == PointOrder::Fortran {
        axes.reverse();
    }
    axes.extend(comps.clone());
    let copy: Vec<f64> = view.view().permuted_axes(axes).iter().copied().collect();
    let per_point = 3usize.pow(C as u32) as isize;
    let comp = std::array::from_fn(|k| 3isize.pow((C - 1 - k) as u32));
    let strided = Strided {
        ptr: copy.as_ptr() as *mut f64,
        comp,
        point: per_point,
    };
    (
        Input {
            strided,
            _copy: Some(copy),
        },
        order,
    )
}

/// Access to an output array, its data at `ptr` with `strides` in bytes; `None` unless its point
/// axes flatten to one stride in `order` (a fresh array allocated in `order` always does).
pub fn output<const C: usize>(
    ptr: *mut f64,
    shape: &[usize],
    strides_bytes: &[isize],
    convention: Convention,
    order: PointOrder,
) -> Option<Strided<C>> {
    let strides: Vec<isize> = strides_bytes.iter().map(|s| s / 8).collect();
    let (comps, point_shape, point_strides) = split::<C>(shape, &strides, convention);
    Some(Strided {
        ptr,
        comp: std::array::from_fn(|k| strides[comps.start + k]),
        point: point_stride(&point_shape, &point_strides, order)?,
    })
}

/// The multi-index of point `p` among `shape` enumerated in `order` (for error messages).
pub fn multi_index(mut p: usize, shape: &[usize], order: PointOrder) -> Vec<usize> {
    let mut index = vec![0; shape.len()];
    let axes: Vec<usize> = match order {
        PointOrder::C => (0..shape.len()).rev().collect(),
        PointOrder::Fortran => (0..shape.len()).collect(),
    };
    for a in axes {
        let n = shape[a].max(1);
        index[a] = p % n;
        p /= n;
    }
    index
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c_and_fortran_point_axes_flatten_and_a_two_axis_slice_does_not() {
        // (q, c) = (4, 5) point axes of a C-contiguous (3, 3, 4, 5) array: strides 5, 1.
        assert_eq!(point_stride(&[4, 5], &[5, 1], PointOrder::C), Some(1));
        assert_eq!(point_stride(&[4, 5], &[5, 1], PointOrder::Fortran), None);
        // Fortran-contiguous: strides 9, 36 (after the two component axes).
        assert_eq!(
            point_stride(&[4, 5], &[9, 36], PointOrder::Fortran),
            Some(9)
        );
        // Every other column of a (4, 10) array still flattens (stride 2); every other row and
        // column of an (8, 10) array does not.
        assert_eq!(point_stride(&[4, 5], &[10, 2], PointOrder::C), Some(2));
        assert_eq!(point_stride(&[4, 5], &[20, 2], PointOrder::C), None);
        assert_eq!(point_stride(&[], &[], PointOrder::C), Some(0));
        assert_eq!(point_stride(&[1, 7], &[99, 3], PointOrder::C), Some(3));
    }

    #[test]
    fn multi_index_inverts_the_enumeration() {
        assert_eq!(multi_index(7, &[4, 5], PointOrder::C), vec![1, 2]);
        assert_eq!(multi_index(7, &[4, 5], PointOrder::Fortran), vec![3, 1]);
    }
}
