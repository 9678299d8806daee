//! A hull file's bilge keels: the optional `<bilge_keels>` element, a child of `<hull>`.
//!
//! ```xml
//! <bilge_keels breadth="0.4" length_fraction="0.3"/>
//! ```
//!
//! `breadth` is one keel's breadth normal to the hull (m, within the hull's length limits);
//! `length_fraction` the fraction of the hull's length that carries keels (`0 < f <= 1`; for a
//! section on its own, the share of its unit length). The keels do not change the panel
//! geometry: only the viscous roll damping estimate ([`crate::viscous::hull_roll_damping`])
//! uses them.

use super::{check_length, plain};
use crate::viscous::BilgeKeels;
use crate::xml::{Element, XmlError};

/// Parses a `<bilge_keels>` element.
pub(super) fn parse(element: &Element) -> Result<BilgeKeels, XmlError> {
    element.only_attributes(&["breadth", "length_fraction"])?;
    element.no_children()?;
    let breadth = element.required_number("breadth")?;
    if breadth <= 0.0 {
        return Err(element.error(format!(
            "breadth=\"{}\" in <bilge_keels> must be > 0 m (leave the element out for no keels)",
            plain(breadth)
        )));
    }
    check_length("breadth in <bilge_keels>", breadth).map_err(|m| element.error(m))?;
    let length_fraction = element.required_number("length_fraction")?;
    if !(length_fraction > 0.0 && length_fraction <= 1.0) {
        return Err(element.error(format!(
            "length_fraction=\"{}\" in <bilge_keels> must be in (0, 1]",
            plain(length_fraction)
        )));
    }
    Ok(BilgeKeels {
        breadth,
        length_fraction,
    })
}

/// The canonical `<bilge_keels>` element (two-space indent), as [`super::Hull::to_xml_string`]
/// writes it.
pub(super) fn to_xml(keels: &BilgeKeels, num: impl Fn(f64) -> String) -> String {
    format!(
        "  <bilge_keels breadth=\"{}\" length_fraction=\"{}\"/>\n",
        num(keels.breadth),
        num(keels.length_fraction)
    )
}

#[cfg(test)]
mod tests;
