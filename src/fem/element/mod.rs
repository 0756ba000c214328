//! The mixed u–p quadrilaterals a user trades speed for accuracy with ([`Element`]). Each is one
//! file that implements [`MixedElement`] on its [`ReferenceElement`] (its shape functions and
//! Gauss rule, and the facts the mesh, the dof numbering, the assembly, the memory model and the
//! VTK writer read) plus one line of `elements!` below. Shared by all: the reference-element
//! machinery and the map to a physical cell ([`mod@reference`]), and the element residual and
//! tangent of the weak form ([`weak_form`]).
//!
//! Local dof order: [u_r⁰, u_z⁰, …, u_r^{n−1}, u_z^{n−1}, p⁰, …]: the displacement on the cell's
//! n nodes, then the pressure dofs (the 4 corner values for Q2/Q1, the one cell value for Q1/P0).
//!
//! Code over the cells stays monomorphised in the element's sizes (`NN`, `NU`, `NP`, `ND`,
//! `NQ`): the run-time [`Element`] is matched once, into a [`PerElement`] value (one value of a
//! [`Typed`] type per element, e.g. the tabulated [`Element::reference`] or the assembly's
//! cells), which [`Visit`] and [`TryMap`] then run on with the sizes as constants.

pub use super::kinematics::{jacobian, jacobian_gradient, jacobian_hessian};
pub use reference::{zeroed, PointGeometry, ReferenceElement};
pub use weak_form::{ElementMatrix, ElementScale, ElementVector};

pub mod reference;
pub mod weak_form;

/// Where a cell's nodes sit on the reference square (ξ, η) ∈ [−1, 1]², in the order of the
/// mesh's connectivity (VTK's order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NodeLayout {
    /// The 4 corners, counter-clockwise from (−1, −1) (VTK_QUAD).
    Corners,
    /// The 3 × 3 lattice: the 4 corners, the 4 edge mid-nodes (edge 0–1, 1–2, 2–3, 3–0), then
    /// the centre (VTK_BIQUADRATIC_QUAD).
    Biquadratic,
}

impl NodeLayout {
    /// Nodes per cell.
    pub const fn nodes(self) -> usize {
        match self {
            NodeLayout::Corners => 4,
            NodeLayout::Biquadratic => 9,
        }
    }

    /// Nodes along a cell side, k: a structured nr × nz mesh has ((k − 1) nr + 1)((k − 1) nz + 1)
    /// nodes.
    pub const fn per_side(self) -> usize {
        match self {
            NodeLayout::Corners => 2,
            NodeLayout::Biquadratic => 3,
        }
    }
}

/// Where an element's pressure dofs live.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PressureLayout {
    /// One at each corner node (the cell's first 4), shared by the cells that meet there: a
    /// continuous field.
    AtCorners,
    /// The cell's own [`Element::pressures`]: discontinuous from cell to cell.
    PerCell,
}

/// One mixed element, implemented on its [`ReferenceElement`] (whose const parameters are the
/// element's sizes): its shape functions and Gauss rule, and what the layers around the element
/// loop need to know of it. Its file in `src/fem/element/` implements this; one line in
/// `elements!` below makes it a choice of [`Element`] (scene files, the CLI,
/// [`super::SolverOptions::element`]).
pub trait MixedElement: Sized {
    /// Name in outputs, e.g. "Q2/Q1" (parsed with or without the slash, in any case).
    const NAME: &'static str;
    /// Where its displacement nodes sit ([`NodeLayout::nodes`] is `NN`).
    const NODE_LAYOUT: NodeLayout;
    /// Where its pressure dofs live.
    const PRESSURE_LAYOUT: PressureLayout;
    /// The node (local index) whose displacement is condensed out of the global system
    /// ([`super::condensation`]): an interior node, coupled to its own cell only.
    const CONDENSED_NODE: Option<usize>;

    /// Its shape functions and Gauss rule, tabulated at the quadrature points.
    fn new() -> Self;

    /// The pressure at each of the cell's nodes (`at_nodes`, `NN` values) from its pressure
    /// dofs `p` (`NP` values), for output.
    fn nodal_pressures(p: &[f64], at_nodes: &mut [f64]);
}

/// A type for each element's sizes (`NN`, `NU`, `NP`, `ND`, `NQ`): what a layer keeps per
/// element in a [`PerElement`] (e.g. the assembly's cells of fixed-size arrays).
pub trait Typed {
    /// The type for one element's sizes.
    type Of<const NN: usize, const NU: usize, const NP: usize, const ND: usize, const NQ: usize>: std::fmt::Debug;
}

/// The tabulated reference elements themselves ([`Element::reference`]).
#[derive(Debug)]
pub struct References;

impl Typed for References {
    type Of<const NN: usize, const NU: usize, const NP: usize, const ND: usize, const NQ: usize> =
        ReferenceElement<NN, NU, NP, ND, NQ>;
}

/// Code run on one element's value of `T` ([`PerElement::visit`]), compiled once per element.
pub trait Visit<T: Typed> {
    /// What it returns.
    type Output;
    /// Runs on `value`, the sizes known at compile time.
    fn visit<const NN: usize, const NU: usize, const NP: usize, const ND: usize, const NQ: usize>(
        self,
        value: &T::Of<NN, NU, NP, ND, NQ>,
    ) -> Self::Output;
}

/// A fallible map from one element's value of `S` to its value of `T` ([`PerElement::try_map`]),
/// compiled once per element.
pub trait TryMap<S: Typed, T: Typed> {
    /// Why it fails.
    type Error;
    /// Maps `value`, the sizes known at compile time.
    fn map<const NN: usize, const NU: usize, const NP: usize, const ND: usize, const NQ: usize>(
        self,
        value: S::Of<NN, NU, NP, ND, NQ>,
    ) -> Result<T::Of<NN, NU, NP, ND, NQ>, Self::Error>;
}

/// The elements: `elements! { file::Reference => Variant, ... }` declares each element's module
/// (`src/fem/element/file.rs`, which implements [`MixedElement`] on `Reference`) and re-exports
/// its reference element, and generates [`Element`] (one variant per line, the first the
/// default), its facts from the [`MixedElement`] implementations, and [`PerElement`].
macro_rules! elements {
    ($($(#[$doc:meta])* $file:ident::$reference:ident => $variant:ident),* $(,)?) => {
        $(mod $file;
        pub use $file::$reference;
        const _: () = assert!(
            $reference::NODES == <$reference as MixedElement>::NODE_LAYOUT.nodes(),
            "the node layout must have NN nodes"
        );)*

        /// The mixed element: a user's choice between accuracy per dof and cost per dof.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
        pub enum Element {
            $($(#[$doc])* $variant,)*
        }

        impl Element {
            /// Every element, in the order of `elements!` (the default first).
            pub const ALL: [Element; [$(Element::$variant),*].len()] = [$(Element::$variant),*];

            /// Nodes per cell.
            pub const fn nodes(self) -> usize {
                match self {
                    $(Element::$variant => $reference::NODES,)*
                }
            }

            /// Quadrature points per cell.
            pub const fn quadrature_points(self) -> usize {
                match self {
                    $(Element::$variant => $reference::POINTS,)*
                }
            }

            /// Pressure dofs per cell (shared with neighbours for [`PressureLayout::AtCorners`],
            /// the cell's own for [`PressureLayout::PerCell`]).
            pub const fn pressures(self) -> usize {
                match self {
                    $(Element::$variant => $reference::PRESSURES,)*
                }
            }

            /// Short name, e.g. "Q2/Q1" ([`MixedElement::NAME`]).
            pub const fn name(self) -> &'static str {
                match self {
                    $(Element::$variant => <$reference as MixedElement>::NAME,)*
                }
            }

            /// Where the nodes of a cell sit ([`MixedElement::NODE_LAYOUT`]).
            pub const fn node_layout(self) -> NodeLayout {
                match self {
                    $(Element::$variant => <$reference as MixedElement>::NODE_LAYOUT,)*
                }
            }

            /// Where the pressure dofs live ([`MixedElement::PRESSURE_LAYOUT`]).
            pub const fn pressure_layout(self) -> PressureLayout {
                match self {
                    $(Element::$variant => <$reference as MixedElement>::PRESSURE_LAYOUT,)*
                }
            }

            /// The node condensed out of the global system, if any
            /// ([`MixedElement::CONDENSED_NODE`]).
            pub const fn condensed_node(self) -> Option<usize> {
                match self {
                    $(Element::$variant => <$reference as MixedElement>::CONDENSED_NODE,)*
                }
            }

            /// The pressure at a cell's nodes from its pressure dofs
            /// ([`MixedElement::nodal_pressures`]).
            pub fn nodal_pressures(self, p: &[f64], at_nodes: &mut [f64]) {
                match self {
                    $(Element::$variant => <$reference as MixedElement>::nodal_pressures(p, at_nodes),)*
                }
            }

            /// The element's tabulated reference element.
            pub fn reference(self) -> PerElement<References> {
                match self {
                    $(Element::$variant => PerElement::$variant(<$reference as MixedElement>::new()),)*
                }
            }
        }

        /// One value of `T`'s type for the sizes of one of the elements: what a layer keeps per
        /// element (e.g. the assembly's cells), so that the code over it is monomorphised.
        #[derive(Debug)]
        pub enum PerElement<T: Typed> {
            $(#[doc = concat!("The value for [`Element::", stringify!($variant), "`].")]
            $variant(
                T::Of<
                    { $reference::NODES },
                    { $reference::DISPLACEMENT_DOFS },
                    { $reference::PRESSURES },
                    { $reference::DOFS },
                    { $reference::POINTS },
                >,
            ),)*
        }

        impl<T: Typed> PerElement<T> {
            /// The element the value is for.
            pub fn element(&self) -> Element {
                match self {
                    $(PerElement::$variant(_) => Element::$variant,)*
                }
            }

            /// Runs `visitor` on the value, compiled for the element's sizes.
            pub fn visit<V: Visit<T>>(&self, visitor: V) -> V::Output {
                match self {
                    $(PerElement::$variant(value) => visitor.visit(value),)*
                }
            }

            /// The value mapped by `map`, compiled for the element's sizes.
            pub fn try_map<U: Typed, M: TryMap<T, U>>(self, map: M) -> Result<PerElement<U>, M::Error> {
                match self {
                    $(PerElement::$variant(value) => Ok(PerElement::$variant(map.map(value)?)),)*
                }
            }
        }
    };
}

// A new element: its file in this directory (`impl MixedElement` on its reference element) and
// one line here.
elements! {
    /// Taylor–Hood Q2/Q1: biquadratic displacement on 9 nodes, continuous bilinear pressure on
    /// the 4 corners, 3 × 3 Gauss. Inf–sup stable; J = 1 holds weakly,
    /// ∫ q (J − 1) dV = 0 for every continuous bilinear q. Second-order displacement.
    #[default]
    q2q1::Q2Q1Reference => Q2Q1,
    /// Q1/P0: bilinear displacement on the 4 corners, one constant pressure per cell, 2 × 2
    /// Gauss: the axisymmetric hybrid element of commercial codes (e.g. Abaqus CAX4H).
    /// Incompressibility holds in the mean per cell, ∫_e (J − 1) dV = 0. A third of the dofs
    /// and 4–8 × less assembly time than Q2/Q1 on the same cells (`examples/fem_scaling.rs`),
    /// but first-order displacement and not inf–sup stable (the pressure may oscillate from
    /// cell to cell near constrained boundaries).
    q1p0::Q1P0Reference => Q1P0,
}

impl std::str::FromStr for Element {
    type Err = String;

    /// An element's name with or without its slash, in any case: "Q2Q1" or "Q2/Q1", "q1p0" or
    /// "Q1/P0".
    fn from_str(s: &str) -> Result<Self, String> {
        let key = |name: &str| name.to_ascii_uppercase().replace('/', "");
        Element::ALL
            .into_iter()
            .find(|e| key(e.name()) == key(s))
            .ok_or_else(|| {
                let names: Vec<&str> = Element::ALL.iter().map(|e| e.name()).collect();
                format!("unknown element {s:?} (expected {})", names.join(" or "))
            })
    }
}

impl std::fmt::Display for Element {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The battery every element gets by its line in `elements!`: its tabulated functions and
/// facts against closed forms that hold for any element.
#[cfg(test)]
mod tests {
    use super::reference::LATTICE;
    use super::*;

    /// Sums over a reference element that closed forms give for any element.
    #[derive(Debug)]
    struct Sums {
        /// max over the points of |Σ_a N_a − 1| and |Σ_a ∂N_a/∂(ξ, η)|.
        shape: f64,
        /// max over the points of |Σ_c M_c − 1| (each element's pressure interpolates constants).
        pressure: f64,
        /// Σ_q w_q (the area of the reference square, 4).
        weights: f64,
        /// Σ dV over the cell [1, 2] × [0, 1] (2π ∫ r dr dz = 3π).
        volume: f64,
        nodes: usize,
    }

    struct Measure;

    impl Visit<References> for Measure {
        type Output = Sums;

        fn visit<
            const NN: usize,
            const NU: usize,
            const NP: usize,
            const ND: usize,
            const NQ: usize,
        >(
            self,
            re: &ReferenceElement<NN, NU, NP, ND, NQ>,
        ) -> Sums {
            let mut shape = 0.0f64;
            let mut pressure = 0.0f64;
            for q in 0..NQ {
                shape = shape.max((re.n[q].iter().sum::<f64>() - 1.0).abs());
                for d in 0..2 {
                    shape = shape.max(re.dn[q].iter().map(|g| g[d]).sum::<f64>().abs());
                }
                pressure = pressure.max((re.m[q].sum() - 1.0).abs());
            }
            // The cell [1, 2] × [0, 1] with its nodes where the layout puts them.
            let x: [[f64; 2]; NN] = std::array::from_fn(|a| {
                [1.0 + 0.5 * LATTICE[a].0 as f64, 0.5 * LATTICE[a].1 as f64]
            });
            let volume = re
                .cell_geometry(&x)
                .map_or(f64::NAN, |g| g.iter().map(|p| p.dv).sum());
            Sums {
                shape,
                pressure,
                weights: re.w.iter().sum(),
                volume,
                nodes: NN,
            }
        }
    }

    #[test]
    fn shape_functions_are_a_partition_of_unity_and_the_rule_integrates_a_mapped_cell() {
        for element in Element::ALL {
            let sums = element.reference().visit(Measure);
            println!("{element}: {sums:?}");
            assert!(sums.shape < 1e-15, "{element}: {sums:?}");
            assert!(sums.pressure < 1e-15, "{element}: {sums:?}");
            assert!((sums.weights - 4.0).abs() < 1e-14, "{element}: {sums:?}");
            let exact = 3.0 * std::f64::consts::PI;
            assert!(
                (sums.volume - exact).abs() < 1e-13 * exact,
                "{element}: {sums:?}"
            );
            assert_eq!(sums.nodes, element.node_layout().nodes());
            assert_eq!(sums.nodes, element.nodes());
        }
    }

    #[test]
    fn nodal_pressures_reproduce_a_constant_pressure() {
        for element in Element::ALL {
            let p = vec![-1.25; element.pressures()];
            let mut at_nodes = vec![0.0; element.nodes()];
            element.nodal_pressures(&p, &mut at_nodes);
            assert!(
                at_nodes.iter().all(|&v| v == -1.25),
                "{element}: {at_nodes:?}"
            );
        }
    }

    #[test]
    fn every_element_is_parsed_back_from_its_name_with_or_without_the_slash() {
        for element in Element::ALL {
            let name = element.name();
            assert_eq!(name.parse::<Element>(), Ok(element));
            assert_eq!(
                name.replace('/', "").to_lowercase().parse::<Element>(),
                Ok(element)
            );
            assert_eq!(element.to_string(), name);
        }
        let error = "Q3".parse::<Element>().unwrap_err();
        assert!(
            Element::ALL.iter().all(|e| error.contains(e.name())),
            "{error}"
        );
    }
}
