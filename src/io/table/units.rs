//! Length units of marker coordinates.

use std::fmt;

/// The unit of `.trc` marker coordinates (the file's `Units` field).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LengthUnit {
    /// `mm`.
    Millimeters,
    /// `cm`.
    Centimeters,
    /// `m`.
    Meters,
}

impl LengthUnit {
    /// Metres per one of this unit (0.001 for millimetres).
    pub fn to_meters_factor(self) -> f64 {
        1.0 / self.per_meter()
    }

    /// How many of this unit make a metre (1000 for millimetres); dividing by it converts
    /// to metres with a single rounding.
    pub fn per_meter(self) -> f64 {
        match self {
            LengthUnit::Millimeters => 1000.0,
            LengthUnit::Centimeters => 100.0,
            LengthUnit::Meters => 1.0,
        }
    }

    /// Reads `mm`, `cm` or `m`, in any case.
    pub fn from_symbol(symbol: &str) -> Option<Self> {
        match symbol.to_ascii_lowercase().as_str() {
            "mm" => Some(LengthUnit::Millimeters),
            "cm" => Some(LengthUnit::Centimeters),
            "m" => Some(LengthUnit::Meters),
            _ => None,
        }
    }

    /// The spelling in a `.trc` file: `mm`, `cm` or `m`.
    pub fn symbol(self) -> &'static str {
        match self {
            LengthUnit::Millimeters => "mm",
            LengthUnit::Centimeters => "cm",
            LengthUnit::Meters => "m",
        }
    }
}

impl fmt::Display for LengthUnit {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        formatter.write_str(self.symbol())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factors_and_spellings() {
        assert_eq!(LengthUnit::Millimeters.to_meters_factor(), 0.001);
        assert_eq!(LengthUnit::Centimeters.to_meters_factor(), 0.01);
        assert_eq!(LengthUnit::Meters.to_meters_factor(), 1.0);
        assert_eq!(LengthUnit::from_symbol("MM"), Some(LengthUnit::Millimeters));
        assert_eq!(LengthUnit::from_symbol("cm"), Some(LengthUnit::Centimeters));
        assert_eq!(LengthUnit::from_symbol("m"), Some(LengthUnit::Meters));
        assert_eq!(LengthUnit::from_symbol("in"), None);
        assert_eq!(LengthUnit::Millimeters.to_string(), "mm");
    }
}
