//! `Volumetric`: a scene's `[incompressibility]` with a volumetric energy U(J), for a finite
//! element code that imposes near incompressibility itself (activemuscle.dolfinx): the volume
//! ratio J̃(p) = (U′)⁻¹(−p) and the compliance 1/U″(J̃) of the perturbed Lagrangian at a batch of
//! pressures ([`activemuscle::volumetric::Volumetric::dilatation`]).

use crate::{py_error, Material};
use activemuscle::models::IncompressibilitySpec;
use numpy::{AllowTypeChange, PyArray1, PyArrayLikeDyn, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A volumetric energy U(J) = U_form(J) + c (J − 1) paired with a material's energy (c makes the
/// passive reference stress free): a scene's `[incompressibility]` keys `kind` ("quadratic",
/// "logarithmic", "4c-giantesio"), `kappa` and, for "4c-giantesio", `mu` (default: the
/// energy's μ).
#[pyclass(frozen, module = "activemuscle._native")]
pub struct Volumetric {
    pub(crate) inner: activemuscle::volumetric::Volumetric,
}

#[pymethods]
impl Volumetric {
    #[new]
    #[pyo3(signature = (material, kind, kappa = None, mu = None))]
    fn new(
        material: &Material,
        kind: String,
        kappa: Option<f64>,
        mu: Option<f64>,
    ) -> PyResult<Self> {
        let kind =
            crate::model::named("kind", &kind).map_err(|e| PyValueError::new_err(e.to_string()))?;
        let spec = IncompressibilitySpec {
            kind: Some(kind),
            kappa,
            mu,
        };
        match spec.build(material.muscle.energy()) {
            Ok(Some(inner)) => Ok(Self { inner }),
            Ok(None) => Err(PyValueError::new_err(
                "kind = \"exact\" (J = 1) has no volumetric energy: give \"quadratic\", \"logarithmic\" or \"4c-giantesio\"",
            )),
            Err(e) => Err(PyValueError::new_err(e.to_string())),
        }
    }

    fn __repr__(&self) -> String {
        format!("Volumetric({})", self.inner.form().formula())
    }

    /// The bulk modulus U″(1) [kPa].
    #[getter]
    fn bulk_modulus(&self) -> f64 {
        self.inner.bulk_modulus()
    }

    /// The pressure of the undeformed body, −U′(1) [kPa] (the passive stress at F = I that U
    /// balances: 0 for the chapter's energy): a start at which J̃ exists for every form.
    #[getter]
    fn reference_pressure(&self) -> PyResult<f64> {
        let [_, du, _] = self.inner.derivatives(1.0).map_err(|e| py_error(&e, ""))?;
        Ok(0.0 - du) // +0.0, not −0.0, where U′(1) = 0
    }

    /// U(J), U′(J), U″(J) [kPa] at a batch of volume ratios: a dict of arrays "energy",
    /// "first", "second".
    fn derivatives<'py>(
        &self,
        py: Python<'py>,
        volume_ratio: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let j = volume_ratio.as_array();
        let mut out = [Vec::new(), Vec::new(), Vec::new()];
        for (i, &j) in j.iter().enumerate() {
            let d = self
                .inner
                .derivatives(j)
                .map_err(|e| py_error(&e, &format!("volume ratio {i}: ")))?;
            for (o, v) in out.iter_mut().zip(d) {
                o.push(v);
            }
        }
        let d = PyDict::new(py);
        for (key, values) in ["energy", "first", "second"].into_iter().zip(out) {
            d.set_item(key, PyArray1::from_vec(py, values))?;
        }
        Ok(d)
    }

    /// At a batch of pressures p [kPa] (any shape, flattened in C order): a dict of arrays
    /// "volume_ratio" J̃(p), with U′(J̃) = −p, and "compliance" 1/U″(J̃) [1/kPa]. A pressure with
    /// no J̃ > 0 raises ArithmeticError naming its index.
    fn dilatation<'py>(
        &self,
        py: Python<'py>,
        pressure: PyArrayLikeDyn<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let p = pressure.as_array();
        let n = p.len();
        let ratio = PyArray1::<f64>::zeros(py, n, false);
        let compliance = PyArray1::<f64>::zeros(py, n, false);
        {
            let mut r = ratio.readwrite();
            let mut c = compliance.readwrite();
            let (r, c) = (r.as_slice_mut()?, c.as_slice_mut()?);
            for (i, &p) in p.iter().enumerate() {
                let (j, k) = self
                    .inner
                    .dilatation(p)
                    .map_err(|e| py_error(&e, &format!("pressure {i}: ")))?;
                r[i] = j;
                c[i] = k;
            }
        }
        let d = PyDict::new(py);
        d.set_item("volume_ratio", ratio)?;
        d.set_item("compliance", compliance)?;
        Ok(d)
    }
}
