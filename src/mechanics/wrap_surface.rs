//! What the wrap objects share: the `quadrant` side rule, `PathWrap`'s `method`, the path over a
//! surface, OpenSim's `WrapAction` with that path, and the dispatch of `wrapLine` to the
//! object's class. Everything is in the wrap object's own frame (m).

use super::spatial::Vec3;
use super::wrap_cylinder::Cylinder;
use super::wrap_ellipsoid::Ellipsoid;
use super::wrap_sphere::Sphere;
use super::wrap_torus::Torus;

/// `quadrant`: the wrap side. `axis` 0, 1, 2 for x, y, z; `sign` ±1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Quadrant {
    pub axis: usize,
    pub sign: i32,
}

impl Quadrant {
    /// OpenSim's spellings (`-x`, `x`, `+x`, `X`, …); `all`/`ALL`/`All`/`Unassigned` give
    /// `Ok(None)`, anything else an error saying so.
    pub fn parse(name: &str) -> Result<Option<Quadrant>, String> {
        let (sign, axis) = match name.strip_prefix('-') {
            Some(axis) => (-1, axis),
            None => (1, name.strip_prefix('+').unwrap_or(name)),
        };
        match axis {
            "x" | "X" => Ok(Some(Quadrant { axis: 0, sign })),
            "y" | "Y" => Ok(Some(Quadrant { axis: 1, sign })),
            "z" | "Z" => Ok(Some(Quadrant { axis: 2, sign })),
            "all" | "ALL" | "All" | "Unassigned" if sign == 1 && !name.starts_with('+') => Ok(None),
            _ => Err(format!("quadrant {name:?} is not one of OpenSim's (+x, -y, all, …)")),
        }
    }
}

/// `PathWrap`'s `method`: how a `WrapEllipsoid` finds its wrapping plane (the other classes
/// have one way only).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WrapMethod {
    /// Frans' axial technique blended with the fan (OpenSim's default).
    Hybrid,
    /// Through the closest surface point to the middle of the chord.
    Midpoint,
    /// Frans' axial technique alone.
    Axial,
}

impl WrapMethod {
    /// OpenSim's spellings (`hybrid`, `Hybrid`, `HYBRID`, …; `Unassigned` is `hybrid`);
    /// anything else an error saying so.
    pub fn parse(name: &str) -> Result<WrapMethod, String> {
        match name {
            "hybrid" | "Hybrid" | "HYBRID" | "Unassigned" => Ok(WrapMethod::Hybrid),
            "midpoint" | "Midpoint" | "MIDPOINT" => Ok(WrapMethod::Midpoint),
            "axial" | "Axial" | "AXIAL" => Ok(WrapMethod::Axial),
            _ => Err(format!("wrapping method {name:?} is not one of OpenSim's (hybrid, midpoint, axial)")),
        }
    }
}

/// The path over the surface, in the wrap object's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePath {
    /// Tangent point next to the segment's first point (m).
    pub r1: Vec3,
    /// Tangent point next to the segment's second point (m).
    pub r2: Vec3,
    /// Length of the surface path from r1 to r2 (m).
    pub length: f64,
}

/// OpenSim's `WrapAction` with the surface path of a wrap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Wrapping {
    /// The segment does not wrap.
    NoWrap,
    /// A point of the segment lies inside the object (for a cylinder: its infinite extension).
    InsideRadius,
    /// The segment wraps; other segments of the path may wrap with a smaller length change.
    Wrapped(SurfacePath),
    /// The straight segment passes through the object: this segment must wrap.
    Mandatory(SurfacePath),
}

/// The surface of a wrap object of a class osim-tune wraps over.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WrapSurface {
    Cylinder(Cylinder),
    Ellipsoid(Ellipsoid),
    Sphere(Sphere),
    Torus(Torus),
}

impl WrapSurface {
    /// `WrapObject::wrapLine`: wraps the segment p1–p2 (m, in the object's frame). `single_wrap`:
    /// the path has only this one `PathWrap` (a cylinder, the torus' too, then keeps its first
    /// tangent points).
    pub fn wrap_line(&self, p1: &Vec3, p2: &Vec3, single_wrap: bool) -> Wrapping {
        match self {
            WrapSurface::Cylinder(cylinder) => cylinder.wrap_line(p1, p2, single_wrap),
            WrapSurface::Ellipsoid(ellipsoid) => ellipsoid.wrap_line(p1, p2),
            WrapSurface::Sphere(sphere) => sphere.wrap_line(p1, p2),
            WrapSurface::Torus(torus) => torus.wrap_line(p1, p2, single_wrap),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrant_names_are_opensims() {
        assert_eq!(Quadrant::parse("-y"), Ok(Some(Quadrant { axis: 1, sign: -1 })));
        assert_eq!(Quadrant::parse("+X"), Ok(Some(Quadrant { axis: 0, sign: 1 })));
        assert_eq!(Quadrant::parse("z"), Ok(Some(Quadrant { axis: 2, sign: 1 })));
        assert_eq!(Quadrant::parse("all"), Ok(None));
        assert_eq!(Quadrant::parse("Unassigned"), Ok(None));
        assert!(Quadrant::parse("+all").is_err() && Quadrant::parse("-all").is_err() && Quadrant::parse("xy").is_err());
    }

    #[test]
    fn method_names_are_opensims() {
        assert_eq!(WrapMethod::parse("HYBRID"), Ok(WrapMethod::Hybrid));
        assert_eq!(WrapMethod::parse("Unassigned"), Ok(WrapMethod::Hybrid));
        assert_eq!(WrapMethod::parse("Midpoint"), Ok(WrapMethod::Midpoint));
        assert_eq!(WrapMethod::parse("axial"), Ok(WrapMethod::Axial));
        assert!(WrapMethod::parse("aXial").is_err() && WrapMethod::parse("").is_err());
    }
}
