//! `StationDefinedFrame` (OpenSim 4.5): a frame built from three stations a, b, c and an origin
//! station, all on one body. `ab_axis` (default `+x`) runs along b − a, `ab_x_ac_axis` (default
//! `+y`, or the axis after ab's when unreadable or parallel, as OpenSim falls back) along
//! (b − a) × (c − a), and the third axis, signed to make the frame right-handed, along
//! ab × (ab × ac).

use std::collections::HashMap;

use nalgebra::{Matrix3, Vector3};

use super::error::ModelError;
use super::frame::{join_socket, opensim_path, FrameIndex, Offset};
use super::orientation::body_fixed_xyz_angles;
use super::reader::ComponentReader;
use crate::io::xml::ElementId;

/// The frame's body and its transform there, from its stations (`stations`: the model's
/// `Station`s by component path).
pub(super) fn station_defined_offset(
    frame: ComponentReader,
    index: &FrameIndex,
    stations: &HashMap<String, ElementId>,
) -> Result<(String, Offset), ModelError> {
    let path = opensim_path(frame.document, frame.element);
    let mut body = None;
    let mut points = Vec::with_capacity(4);
    for socket in ["socket_point_a", "socket_point_b", "socket_point_c", "socket_origin_point"] {
        let target = frame.text(socket)?;
        let station = stations.get(&join_socket(&path, &target)).ok_or_else(|| frame.unknown(&format!("Station in <{socket}>"), &target))?;
        let station = frame.at(*station);
        let chain = index.resolve(station, &station.text("socket_parent_frame")?, "socket_parent_frame")?;
        match &body {
            None => body = Some(chain.body.clone()),
            Some(first) if *first != chain.body => return Err(frame.bad(socket, &format!("a station on {first}, as point_a"), &chain.body)),
            Some(_) => {}
        }
        points.push(Vector3::from(chain.point_in_body(station.vec3_or("location", [0.0; 3])?)));
    }
    let (a, b, c, origin) = (points[0], points[1], points[2], points[3]);
    if a == b || a == c || b == c {
        return Err(frame.bad("socket_point_c", "three stations at different locations (a triangle)", "coincident stations"));
    }
    let ab = (b - a).normalize();
    let normal = ab.cross(&(c - a).normalize()).normalize();
    let axes = axis_mapping(frame)?;
    let mut rotation = Matrix3::zeros();
    for ((axis, sign), direction) in axes.into_iter().zip([ab, normal, ab.cross(&normal).normalize()]) {
        rotation.set_column(axis, &(sign * direction));
    }
    let offset = Offset { translation: origin.into(), orientation: body_fixed_xyz_angles(&rotation) };
    Ok((body.unwrap_or_default(), offset))
}

/// (axis index, sign) of ab, ab × ac and the third basis vector.
fn axis_mapping(frame: ComponentReader) -> Result<[(usize, f64); 3], ModelError> {
    let ab = parse_direction(&frame.optional_text("ab_axis").unwrap_or_else(|| "+x".into())).unwrap_or((0, 1.0));
    let next = ((ab.0 + 1) % 3, 1.0);
    let normal = parse_direction(&frame.optional_text("ab_x_ac_axis").unwrap_or_else(|| "+y".into())).filter(|d| d.0 != ab.0).unwrap_or(next);
    let third = 3 - ab.0 - normal.0;
    // e_third = sign · e_ab × e_normal, with e_i × e_(i+1) = +e_(i+2).
    let cyclic = if (ab.0 + 1) % 3 == normal.0 { 1.0 } else { -1.0 };
    Ok([ab, normal, (third, ab.1 * normal.1 * cyclic)])
}

/// `+x`, `-y`, `z`, … as (axis index, sign); `None` for anything else.
fn parse_direction(text: &str) -> Option<(usize, f64)> {
    let text = text.trim();
    let (sign, axis) = match text.strip_prefix('-') {
        Some(rest) => (-1.0, rest),
        None => (1.0, text.strip_prefix('+').unwrap_or(text)),
    };
    let index = match axis.chars().next()?.to_ascii_lowercase() {
        'x' => 0,
        'y' => 1,
        'z' => 2,
        _ => return None,
    };
    Some((index, sign))
}

#[cfg(test)]
mod tests {
    use super::parse_direction;

    #[test]
    fn directions_read_as_opensim_reads_them() {
        assert_eq!(parse_direction("+x"), Some((0, 1.0)));
        assert_eq!(parse_direction("-Z"), Some((2, -1.0)));
        assert_eq!(parse_direction("y"), Some((1, 1.0)));
        assert_eq!(parse_direction("+"), None);
        assert_eq!(parse_direction("w"), None);
    }
}
