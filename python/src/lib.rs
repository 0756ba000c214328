//! `activemuscle._native`: the engine's material point on numpy arrays.
//!
//! One class, [`Material`]: built from keyword choices (the names and defaults of a scene, see
//! [`model`]), it evaluates a batch of deformation gradients F at once — felupe's (3, 3, ...) or
//! (..., 3, 3), zero-copy — returning P = ∂Ŵ/∂F (without the pressure term), A = ∂P/∂F
//! (A[i, j, k, l] = ∂P_ij/∂F_kl, exact; not major-symmetric for the frozen coupling), γ, the fibre
//! stretch, Ŵ and dP/dγ = ∂²Ŵ/∂F∂γ at F held. Large batches run on rayon's threads with the GIL
//! released; nothing is allocated per point. Errors become Python exceptions carrying the core's
//! message and the index of the first failing point.

mod layout;
pub mod model;
mod scene;
mod volumetric;

use activemuscle::active::Law;
use activemuscle::energy::Energy;
use activemuscle::fit::Parametric;
use activemuscle::invariants::{Kinematics, FULL};
use activemuscle::response::Order;
use activemuscle::StrainEnergy;
use activemuscle::{Error, Muscle};
use layout::{Convention, Input, PointOrder, Strided};
use nalgebra::{Matrix3, Vector3};
use numpy::{
    AllowTypeChange, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods, PyReadwriteArrayDyn,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyArithmeticError, PyFloatingPointError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

/// Batches of at least this many points run on rayon's threads.
const PARALLEL_MIN_POINTS: usize = 2048;
/// Points per rayon task.
const CHUNK: usize = 512;

fn py_error(e: &Error, context: &str) -> PyErr {
    let msg = format!("{context}{e}");
    match e {
        Error::NonFinite { .. } => PyFloatingPointError::new_err(msg),
        Error::NoSolution { .. } => PyArithmeticError::new_err(msg),
        _ => PyValueError::new_err(msg),
    }
}

fn parse_order(order: &str) -> PyResult<Order> {
    match order {
        "energy" => Ok(Order::Energy),
        "stress" => Ok(Order::Stress),
        "tangent" => Ok(Order::Tangent),
        other => Err(PyValueError::new_err(format!(
            "order = {other:?}: must be \"energy\", \"stress\" or \"tangent\""
        ))),
    }
}

/// The fibre direction, normalised; a finite non-zero vector (as a scene's `material.fibre`).
#[inline(always)]
fn unit_fibre(m: Vector3<f64>) -> Result<Vector3<f64>, Error> {
    // Scaled by its largest component first, as a scene's `fibre` is, so that neither
    // [1e-300, 0, 0] underflows nor [1e300, 1e300, 0] overflows on the way to its norm.
    let largest = m.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if m.iter().all(|x| x.is_finite()) && largest > 0.0 {
        let scaled = m / largest;
        Ok(scaled / scaled.norm())
    } else {
        Err(Error::InvalidParameter {
            name: "fibre",
            value: largest,
            rule: "the fibre direction must be a finite, non-zero vector (its largest component is shown)",
        })
    }
}

/// The output arrays of one evaluation, as raw strided access.
#[derive(Clone, Copy)]
struct Outputs {
    gamma: Strided<0>,
    fibre_stretch: Strided<0>,
    energy: Strided<0>,
    stress: Option<Strided<2>>,
    tangent: Option<Strided<4>>,
    dstress_dgamma: Option<Strided<2>>,
}

/// Everything a batch evaluation reads.
struct Batch<'a> {
    muscle: &'a Muscle<Energy>,
    order: Order,
    f: Strided<2>,
    fibre: Strided<1>,
    out: Outputs,
}

impl Batch<'_> {
    /// Points `range`, in order; the first failing point and why.
    fn run(&self, range: std::ops::Range<usize>) -> Result<(), (usize, Error)> {
        for p in range {
            self.point(p).map_err(|e| (p, e))?;
        }
        Ok(())
    }

    #[inline(always)]
    fn point(&self, p: usize) -> Result<(), Error> {
        // SAFETY: p < n, the arrays hold n points with the component extents used (built so in
        // `Material::evaluate`), and each point is written by one thread only.
        unsafe {
            let f = Matrix3::from_fn(|i, j| self.f.get(p, [i, j]));
            let m = unit_fibre(Vector3::from_fn(|i, _| self.fibre.get(p, [i])))?;
            let r = self
                .muscle
                .respond(&Kinematics::new(&f, &m)?, self.order, &FULL)?;
            let o = &self.out;
            o.gamma.set(p, [], r.gamma);
            o.fibre_stretch.set(p, [], r.fibre_stretch);
            o.energy.set(p, [], r.energy);
            if let (Some(s), Some(v)) = (o.stress, r.stress) {
                for a in 0..9 {
                    s.set(p, [a / 3, a % 3], v[a]);
                }
            }
            if let (Some(s), Some(v)) = (o.dstress_dgamma, r.dstress_dgamma) {
                for a in 0..9 {
                    s.set(p, [a / 3, a % 3], v[a]);
                }
            }
            if let (Some(t), Some(k)) = (o.tangent, r.tangent) {
                for a in 0..9 {
                    for b in 0..9 {
                        t.set(p, [a / 3, a % 3, b / 3, b % 3], k[(a, b)]);
                    }
                }
            }
        }
        Ok(())
    }

    /// All `n` points, in parallel when asked and large; the error of the lowest failing point.
    fn run_all(&self, n: usize, parallel: bool) -> Result<(), (usize, Error)> {
        if !parallel || n < PARALLEL_MIN_POINTS {
            return self.run(0..n);
        }
        let chunks = n.div_ceil(CHUNK);
        (0..chunks)
            .into_par_iter()
            .map(|c| self.run(c * CHUNK..((c + 1) * CHUNK).min(n)))
            .reduce(
                || Ok(()),
                |a, b| match (a, b) {
                    (Err(x), Err(y)) => Err(if x.0 <= y.0 { x } else { y }),
                    (Err(x), _) | (_, Err(x)) => Err(x),
                    _ => Ok(()),
                },
            )
    }
}

/// An output array and strided access to its `C` component axes; `_borrow` holds the caller's
/// array read-write for the evaluation.
struct Output<'py, const C: usize> {
    array: Bound<'py, PyArrayDyn<f64>>,
    strided: Strided<C>,
    _borrow: Option<PyReadwriteArrayDyn<'py, f64>>,
}

/// The output `key` of `shape` in `order`: the caller's `out[key]` if given — float64, writeable,
/// of `shape`, its point axes flattening in F's point order; numpy's borrow checker refuses an
/// array given twice or overlapping F or the fibres — else a fresh, uninitialised array. Every
/// entry is written before Python sees a fresh array (a failing point leaves the caller's arrays
/// partly written).
fn output<'py, const C: usize>(
    py: Python<'py>,
    out: Option<&Bound<'py, PyDict>>,
    key: &str,
    shape: &[usize],
    convention: Convention,
    order: PointOrder,
) -> PyResult<Output<'py, C>> {
    let bad = |rule: String| PyValueError::new_err(format!("out[{key:?}]: {rule}"));
    let (array, borrow) = match out.map(|o| o.get_item(key)).transpose()?.flatten() {
        // SAFETY: the evaluation writes every entry (or the array is dropped with the error).
        None => (
            unsafe { PyArrayDyn::<f64>::new(py, shape, order == PointOrder::Fortran) },
            None,
        ),
        Some(given) => {
            let array = given
                .cast::<PyArrayDyn<f64>>()
                .map_err(|_| bad("must be a numpy array of float64".into()))?
                .clone();
            if array.shape() != shape {
                return Err(bad(format!(
                    "has shape {:?}: must be {shape:?}",
                    array.shape()
                )));
            }
            let borrow = array.try_readwrite().map_err(|e| {
                bad(format!(
                    "cannot be written ({e}): it must be writeable and share no memory with F, the fibres or another output"
                ))
            })?;
            (array, Some(borrow))
        }
    };
    // A fresh array allocated in `order` always flattens.
    let strided = layout::output::<C>(
        array.data(),
        array.shape(),
        array.strides(),
        convention,
        order,
    )
    .ok_or_else(|| {
        bad(format!(
            "its point axes must flatten to one stride in F's point order ({order:?}), like a contiguous array"
        ))
    })?;
    Ok(Output {
        array,
        strided,
        _borrow: borrow,
    })
}

/// The keys `evaluate` returns at `order`.
fn output_keys(order: Order) -> &'static [&'static str] {
    match order {
        Order::Energy => &["gamma", "fibre_stretch", "energy"],
        Order::Stress => &["gamma", "fibre_stretch", "energy", "stress"],
        Order::Tangent => &[
            "gamma",
            "fibre_stretch",
            "energy",
            "stress",
            "tangent",
            "dstress_dgamma",
        ],
    }
}

/// Refuses a key of `out` that is not among `keys`.
fn check_out_keys(out: Option<&Bound<'_, PyDict>>, keys: &[&str]) -> PyResult<()> {
    if let Some(o) = out {
        for k in o.keys() {
            let k: String = k.extract()?;
            if !keys.contains(&k.as_str()) {
                return Err(PyValueError::new_err(format!(
                    "out[{k:?}]: not an output of this evaluation, which returns {keys:?}"
                )));
            }
        }
    }
    Ok(())
}

/// The extents of F's point axes (those that are not its two component axes).
fn point_shape_of(shape: &[usize], convention: Convention) -> Vec<usize> {
    let comps = convention.component_axes(shape.len(), 2);
    (0..shape.len())
        .filter(|a| !comps.contains(a))
        .map(|a| shape[a])
        .collect()
}

/// Strided access to the fibre directions: one vector (3,) for every point, or one per point in
/// F's convention and point order.
fn fibre_input(
    fibre_view: &numpy::ndarray::ArrayViewD<f64>,
    convention: Convention,
    point_shape: &[usize],
    point_order: PointOrder,
) -> PyResult<Input<1>> {
    if fibre_view.shape() == [3] {
        // No point axes: the point stride is 0, every point reads the one vector.
        Ok(layout::input(fibre_view, Convention::Trailing, None).0)
    } else {
        let expected = convention.shape(point_shape, 1, 3);
        if fibre_view.shape() != expected.as_slice() {
            return Err(PyValueError::new_err(format!(
                "fibre has shape {:?}: must be (3,) or one vector per point, {:?}",
                fibre_view.shape(),
                expected
            )));
        }
        Ok(layout::input(fibre_view, convention, Some(point_order)).0)
    }
}

/// The output arrays of one `evaluate` (those its order asks for).
struct BatchOutputs<'py> {
    gamma: Output<'py, 0>,
    fibre_stretch: Output<'py, 0>,
    energy: Output<'py, 0>,
    stress: Option<Output<'py, 2>>,
    tangent: Option<Output<'py, 4>>,
    dstress_dgamma: Option<Output<'py, 2>>,
}

impl<'py> BatchOutputs<'py> {
    /// The arrays of `order` over points of `point_shape` (see [`output`]).
    fn new(
        py: Python<'py>,
        out: Option<&Bound<'py, PyDict>>,
        order: Order,
        point_shape: &[usize],
        convention: Convention,
        point_order: PointOrder,
    ) -> PyResult<Self> {
        let tensor_shape = convention.shape(point_shape, 2, 3);
        let scalar = |key| output::<0>(py, out, key, point_shape, convention, point_order);
        let tensor = |key| output::<2>(py, out, key, &tensor_shape, convention, point_order);
        let gamma = scalar("gamma")?;
        let fibre_stretch = scalar("fibre_stretch")?;
        let energy = scalar("energy")?;
        let stress = (order >= Order::Stress)
            .then(|| tensor("stress"))
            .transpose()?;
        let dstress_dgamma = (order == Order::Tangent)
            .then(|| tensor("dstress_dgamma"))
            .transpose()?;
        let tangent = (order == Order::Tangent)
            .then(|| {
                let shape = convention.shape(point_shape, 4, 3);
                output::<4>(py, out, "tangent", &shape, convention, point_order)
            })
            .transpose()?;
        Ok(Self {
            gamma,
            fibre_stretch,
            energy,
            stress,
            tangent,
            dstress_dgamma,
        })
    }

    /// Raw strided access to the arrays, for the batch.
    fn strided(&self) -> Outputs {
        Outputs {
            gamma: self.gamma.strided,
            fibre_stretch: self.fibre_stretch.strided,
            energy: self.energy.strided,
            stress: self.stress.as_ref().map(|s| s.strided),
            tangent: self.tangent.as_ref().map(|s| s.strided),
            dstress_dgamma: self.dstress_dgamma.as_ref().map(|s| s.strided),
        }
    }

    /// The dict `evaluate` returns.
    fn into_dict(self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("gamma", self.gamma.array)?;
        d.set_item("fibre_stretch", self.fibre_stretch.array)?;
        d.set_item("energy", self.energy.array)?;
        if let Some(a) = self.stress {
            d.set_item("stress", a.array)?;
        }
        if let Some(a) = self.tangent {
            d.set_item("tangent", a.array)?;
        }
        if let Some(a) = self.dstress_dgamma {
            d.set_item("dstress_dgamma", a.array)?;
        }
        Ok(d)
    }
}

/// Active skeletal muscle at material points (Giantesio & Musesti): an energy, an activation law,
/// a damage and a coupling.
///
/// Keywords and defaults are those of a scene's `[material]` and `[activation]` tables
/// (scenes/paper.toml); parameters left out take the chapter's values.
#[pyclass(frozen, module = "activemuscle._native")]
struct Material {
    muscle: Muscle<Energy>,
}

#[pymethods]
impl Material {
    /// Keywords: a scene's `[material]` and `[activation]` keys (energy, its parameters by name,
    /// fibre excepted; approach, curve and its parameters by name, law, coupling, frozen_tangent,
    /// damage, explicit = {a, b}, below_minimum, map, representation, table_stretches,
    /// force_velocity = {min_rate, ke, kc, de, dc}), and gamma for law = "constant". The
    /// parameter names come from the registries of energies and curves.
    #[new]
    #[pyo3(signature = (**choices))]
    fn new(choices: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let mut c = model::Choices::default();
        if let Some(d) = choices {
            for (key, value) in d.iter() {
                let key: String = key.extract()?;
                c.take(&key, &value)?;
            }
        }
        let muscle = c
            .muscle()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Self { muscle })
    }

    fn __repr__(&self) -> String {
        let e = self.muscle.energy();
        let params: Vec<String> = e
            .parameter_names()
            .iter()
            .zip(e.parameter_values())
            .map(|(n, v)| format!("{n}={v}"))
            .collect();
        // An approach without a law (active stress) is named, never a law it does not have.
        let model = match self.muscle.fibre_energy() {
            Some((approach, _)) => format!("approach={:?}", approach.name()),
            None => format!(
                "law={:?}, coupling={:?}",
                self.muscle.law().name(),
                self.muscle.coupling().name()
            ),
        };
        format!(
            "Material(energy={:?}, {}, {model}, damage={})",
            e.name(),
            params.join(", "),
            self.muscle.damage()
        )
    }

    /// Whether the tangent is major-symmetric: every coupling but the exact frozen one, and any
    /// coupling of a law with g′ = 0 (passive, constant).
    #[getter]
    fn symmetric_tangent(&self) -> bool {
        self.muscle.coupling().symmetric_tangent()
            || matches!(self.muscle.law(), Law::Passive | Law::Constant(_))
    }

    /// Evaluates the material at every point of a batch.
    ///
    /// F: deformation gradients, shape (3, 3, ...) (felupe's trailing axes) or (..., 3, 3);
    /// fibre: the reference fibre direction, one vector (3,) or one per point, (3, ...) or
    /// (..., 3) like F (normalised here); order: "energy", "stress" or "tangent";
    /// layout: "trailing", "leading" or None (from F's shape; ambiguous shapes must say).
    /// Returns a dict of arrays: "gamma", "fibre_stretch", "energy" [kPa] over the points,
    /// "stress" P [kPa] like F (order ≥ "stress"), "tangent" A [kPa] with
    /// A[i, j, k, l] = ∂P_ij/∂F_kl, shape (3, 3, 3, 3, ...) or (..., 3, 3, 3, 3), and
    /// "dstress_dgamma" dP/dγ [kPa] like F (order "tangent").
    ///
    /// out: a dict of preallocated arrays to write into (any of the returned keys, each of the
    /// returned shape, float64, writeable, its point axes contiguous in F's order); the result
    /// then holds those same arrays. Saves allocating and first touching fresh output memory on
    /// repeated calls.
    #[pyo3(signature = (f, fibre = None, *, order = "tangent", layout = None, parallel = true, out = None))]
    #[allow(clippy::too_many_arguments)]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        f: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
        fibre: Option<PyArrayLikeDyn<'py, f64, AllowTypeChange>>,
        order: &str,
        layout: Option<&str>,
        parallel: bool,
        out: Option<Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let order = parse_order(order)?;
        let out = out.as_ref();
        check_out_keys(out, output_keys(order))?;
        let f_view = f.as_array();
        let convention = convention_of(f_view.shape(), layout)?;
        let point_shape = point_shape_of(f_view.shape(), convention);
        let n: usize = point_shape.iter().product();
        let (f_in, point_order): (Input<2>, _) = layout::input(&f_view, convention, None);
        let default_fibre;
        let fibre_view = match &fibre {
            Some(a) => a.as_array(),
            None => {
                default_fibre = numpy::ndarray::arr1(&[1.0, 0.0, 0.0]).into_dyn();
                default_fibre.view()
            }
        };
        let fibre_in = fibre_input(&fibre_view, convention, &point_shape, point_order)?;
        let outputs = BatchOutputs::new(py, out, order, &point_shape, convention, point_order)?;
        let batch = Batch {
            muscle: &self.muscle,
            order,
            f: f_in.strided,
            fibre: fibre_in.strided,
            out: outputs.strided(),
        };
        py.detach(|| batch.run_all(n, parallel)).map_err(|(p, e)| {
            let index = layout::multi_index(p, &point_shape, point_order);
            py_error(&e, &format!("point {index:?} of F's point axes: "))
        })?;
        drop(f_in);
        drop(fibre_in);
        outputs.into_dict(py)
    }

    /// The core's answer at one point, by the single-point Rust API (no batch machinery):
    /// a dict of nested lists with the keys of `evaluate` (for tests of the batch path).
    #[pyo3(signature = (f, fibre = [1.0, 0.0, 0.0], *, order = "tangent"))]
    fn respond<'py>(
        &self,
        py: Python<'py>,
        f: [[f64; 3]; 3],
        fibre: [f64; 3],
        order: &str,
    ) -> PyResult<Bound<'py, PyDict>> {
        let order = parse_order(order)?;
        let f = Matrix3::from_fn(|i, j| f[i][j]);
        let r = unit_fibre(Vector3::from(fibre))
            .and_then(|m| Kinematics::new(&f, &m))
            .and_then(|kin| self.muscle.respond(&kin, order, &FULL))
            .map_err(|e| py_error(&e, ""))?;
        let d = PyDict::new(py);
        d.set_item("gamma", r.gamma)?;
        d.set_item("fibre_stretch", r.fibre_stretch)?;
        d.set_item("energy", r.energy)?;
        let matrix = |v: &[f64]| -> Vec<Vec<f64>> { v.chunks(3).map(<[f64]>::to_vec).collect() };
        if let Some(s) = r.stress {
            d.set_item("stress", matrix(s.as_slice()))?;
        }
        if let Some(s) = r.dstress_dgamma {
            d.set_item("dstress_dgamma", matrix(s.as_slice()))?;
        }
        if let Some(t) = r.tangent {
            // Row-major 9 × 9 → A[i][j][k][l].
            let a: Vec<Vec<Vec<Vec<f64>>>> = (0..9)
                .map(|row| {
                    (0..9)
                        .map(|col| t[(row, col)])
                        .collect::<Vec<_>>()
                        .chunks(3)
                        .map(<[f64]>::to_vec)
                        .collect()
                })
                .collect::<Vec<Vec<Vec<f64>>>>()
                .chunks(3)
                .map(<[Vec<Vec<f64>>]>::to_vec)
                .collect();
            d.set_item("tangent", a)?;
        }
        Ok(d)
    }

    /// P, A = ∂P/∂F and dP/dγ at a held activation γ by the slow reference route (dual numbers
    /// over F's nine entries and γ, `activemuscle::oracle`), as nested lists: an independent
    /// derivative route for tests.
    #[pyo3(signature = (f, gamma, fibre = [1.0, 0.0, 0.0]))]
    fn oracle<'py>(
        &self,
        py: Python<'py>,
        f: [[f64; 3]; 3],
        gamma: f64,
        fibre: [f64; 3],
    ) -> PyResult<Bound<'py, PyDict>> {
        let f = Matrix3::from_fn(|i, j| f[i][j]);
        let m = unit_fibre(Vector3::from(fibre)).map_err(|e| py_error(&e, ""))?;
        let r = activemuscle::oracle::full_response(self.muscle.energy(), &f, &m, gamma)
            .map_err(|e| py_error(&e, ""))?;
        let d = PyDict::new(py);
        let row_major = |i: usize, j: usize| 3 * i + j;
        let p: Vec<Vec<f64>> = (0..3)
            .map(|i| (0..3).map(|j| r.stress[row_major(i, j)]).collect())
            .collect();
        let rate: Vec<Vec<f64>> = (0..3)
            .map(|i| (0..3).map(|j| r.dstress_dgamma[row_major(i, j)]).collect())
            .collect();
        let a: Vec<Vec<Vec<Vec<f64>>>> = (0..3)
            .map(|i| {
                (0..3)
                    .map(|j| {
                        (0..3)
                            .map(|k| {
                                (0..3)
                                    .map(|l| r.tangent[(row_major(i, j), row_major(k, l))])
                                    .collect()
                            })
                            .collect()
                    })
                    .collect()
            })
            .collect();
        d.set_item("energy", r.energy)?;
        d.set_item("stress", p)?;
        d.set_item("tangent", a)?;
        d.set_item("dstress_dgamma", rate)?;
        Ok(d)
    }

    /// The Taylor test of the tangent at one state (`activemuscle::tangent_check`): F and the
    /// direction dF as 3 × 3 (dF scaled to unit Frobenius norm), the reference fibre, the steps
    /// h (default 2^-6 … 2^-20, each in (0, 1)), and with table=True a comparison with the law in
    /// its other representation (a table build). Returns a dict: "h", "r0" = |P(F + h dF) − P(F)|
    /// and "r1" = |P(F + h dF) − P(F) − h A:dF| [kPa] (numpy arrays, masked where the material
    /// cannot be evaluated at F + h dF), "orders_0", "orders_1" (per pair of steps, masked below
    /// the rounding floor "floor"), "order_0", "order_1" (medians), "least_order_1", "fd_error"
    /// (|A_fd − A|/|A| by central differences), "asymmetry" (|A − Aᵀ|/|A|), "fd_asymmetry",
    /// "asymmetry_reason", "approximations" ({name: |Ã − A|/|A|}), "ellipticity" (least
    /// a·Q(N)a/|A|), "flag" and "reason" (why an order drops, or None), "notes".
    #[pyo3(signature = (f, df, fibre = [1.0, 0.0, 0.0], *, h = None, table = false))]
    fn taylor_test<'py>(
        &self,
        py: Python<'py>,
        f: [[f64; 3]; 3],
        df: [[f64; 3]; 3],
        fibre: [f64; 3],
        h: Option<Vec<f64>>,
        table: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        use activemuscle::tangent_check::{halvings, taylor_test, MusclePoint};
        let (f, df) = (
            Matrix3::from_fn(|i, j| f[i][j]),
            Matrix3::from_fn(|i, j| df[i][j]),
        );
        let report = py
            .detach(|| {
                let h = match h {
                    Some(h) => h,
                    None => halvings(2f64.powi(-6), 2f64.powi(-20))?,
                };
                let mut point = MusclePoint::new(self.muscle.clone(), Vector3::from(fibre))?;
                if table {
                    point = point.with_table_comparison(Default::default())?;
                }
                taylor_test(&point, &f, &df, &h)
            })
            .map_err(|e| py_error(&e, ""))?;
        taylor_dict(py, &report)
    }

    /// Homogeneous uniaxial tension along the fibres at each stretch λ (lateral faces
    /// traction-free; incompressible, or nearly so with a `Volumetric` energy): a dict of arrays
    /// "stretch", "stress" (nominal P [kPa]), "gamma".
    #[pyo3(signature = (stretches, volumetric = None))]
    fn uniaxial<'py>(
        &self,
        py: Python<'py>,
        stretches: Vec<f64>,
        volumetric: Option<PyRef<'py, volumetric::Volumetric>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let mut stress = Vec::with_capacity(stretches.len());
        let mut gamma = Vec::with_capacity(stretches.len());
        let volumetric = volumetric.as_ref().map(|v| &v.inner);
        for &l in &stretches {
            let point = activemuscle::uniaxial::point(
                &self.muscle,
                volumetric,
                activemuscle::uniaxial::Direction::Along,
                l,
            )
            .map_err(|e| py_error(&e, &format!("stretch {l}: ")))?;
            stress.push(point.stress);
            gamma.push(point.gamma);
        }
        let d = PyDict::new(py);
        d.set_item("stretch", numpy::PyArray1::from_vec(py, stretches))?;
        d.set_item("stress", numpy::PyArray1::from_vec(py, stress))?;
        d.set_item("gamma", numpy::PyArray1::from_vec(py, gamma))?;
        Ok(d)
    }
}

/// A float array masked where a value is missing (`numpy.ma`, never a NaN).
fn masked<'py>(py: Python<'py>, values: &[Option<f64>]) -> PyResult<Bound<'py, PyAny>> {
    let data: Vec<f64> = values.iter().map(|v| v.unwrap_or(0.0)).collect();
    let mask: Vec<bool> = values.iter().map(Option::is_none).collect();
    let kwargs = PyDict::new(py);
    kwargs.set_item("mask", numpy::PyArray1::from_vec(py, mask))?;
    py.import("numpy.ma")?.call_method(
        "masked_array",
        (numpy::PyArray1::from_vec(py, data),),
        Some(&kwargs),
    )
}

/// A Taylor report as Python's dict (see `Material.taylor_test`).
fn taylor_dict<'py>(
    py: Python<'py>,
    report: &activemuscle::tangent_check::TaylorReport,
) -> PyResult<Bound<'py, PyDict>> {
    let (r, s) = (&report.remainders, &report.state);
    let d = PyDict::new(py);
    d.set_item("h", numpy::PyArray1::from_vec(py, r.h.clone()))?;
    d.set_item("r0", masked(py, &r.r0)?)?;
    d.set_item("r1", masked(py, &r.r1)?)?;
    d.set_item("orders_0", masked(py, &r.orders_0)?)?;
    d.set_item("orders_1", masked(py, &r.orders_1)?)?;
    d.set_item("order_0", r.order_0)?;
    d.set_item("order_1", r.order_1)?;
    d.set_item("least_order_1", r.least_order_1)?;
    d.set_item("floor", r.floor)?;
    d.set_item("fd_error", s.fd_error)?;
    d.set_item("asymmetry", s.asymmetry)?;
    d.set_item("fd_asymmetry", s.fd_asymmetry)?;
    d.set_item("asymmetry_reason", s.asymmetry_reason.clone())?;
    let approximations = PyDict::new(py);
    for (name, error) in &s.approximations {
        approximations.set_item(name, error)?;
    }
    d.set_item("approximations", approximations)?;
    d.set_item("ellipticity", s.ellipticity.map(|e| e.relative))?;
    d.set_item("flag", r.flag.as_ref().map(|f| f.kind()))?;
    d.set_item("reason", r.flag.as_ref().map(|f| f.reason()))?;
    let mut notes = s.notes.clone();
    if let Some((h, why)) = &r.unevaluable {
        notes.push(format!("not evaluable at h = {h}: {why}"));
    }
    d.set_item("notes", notes)?;
    Ok(d)
}

/// The convention of an F of `shape`: given, or read from the shape.
fn convention_of(shape: &[usize], layout: Option<&str>) -> PyResult<Convention> {
    let nd = shape.len();
    let trailing = nd >= 2 && shape[0] == 3 && shape[1] == 3;
    let leading = nd >= 2 && shape[nd - 2] == 3 && shape[nd - 1] == 3;
    let convention = match layout {
        Some("trailing") => Convention::Trailing,
        Some("leading") => Convention::Leading,
        Some(other) => {
            return Err(PyValueError::new_err(format!(
                "layout = {other:?}: must be \"trailing\" (F of shape (3, 3, ...), felupe's) or \"leading\" ((..., 3, 3))"
            )))
        }
        None if nd == 2 || (trailing && !leading) => Convention::Trailing,
        None if leading && !trailing => Convention::Leading,
        None if trailing => {
            return Err(PyValueError::new_err(format!(
                "F of shape {shape:?} is ambiguous: pass layout=\"trailing\" (felupe's (3, 3, ...)) or layout=\"leading\" ((..., 3, 3))"
            )))
        }
        None => Convention::Trailing,
    };
    let ok = match convention {
        Convention::Trailing => trailing,
        Convention::Leading => leading,
    };
    if !ok {
        return Err(PyValueError::new_err(format!(
            "F has shape {shape:?}: must be (3, 3, ...) (felupe's trailing axes) or (..., 3, 3)"
        )));
    }
    Ok(convention)
}

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // The pool is bounded before any batch runs on it, as the command line bounds it.
    if let Some(notice) = activemuscle::threads::limit_global_pool() {
        let message = std::ffi::CString::new(notice).unwrap_or_default();
        PyErr::warn(
            m.py(),
            &m.py().get_type::<pyo3::exceptions::PyRuntimeWarning>(),
            &message,
            1,
        )?;
    }
    m.add_class::<Material>()?;
    m.add_class::<volumetric::Volumetric>()?;
    m.add_function(wrap_pyfunction!(scene::run_scene, m)?)?;
    m.add_function(wrap_pyfunction!(scene::check_scene, m)?)?;
    m.add("__doc__", "activemuscle's material point on numpy arrays")?;
    Ok(())
}
