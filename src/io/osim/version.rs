//! Document versions (`<OpenSimDocument Version="40000">`) and the dialects they imply.

/// The dialect of an OpenSim document, which decides where components live (e.g. 3.x nests joints
/// in bodies and names markers' bodies with `<body>`; 4.x uses sockets).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Dialect {
    /// OpenSim 2.x (e.g. `20302`): only tool setup files are read in this dialect.
    V2,
    /// OpenSim 3.x (`30000`–`30499`; every 3.x release wrote `30000`).
    V3,
    /// OpenSim 4.x (`40000`…, and `30517`, the last 4.0 development format, which OpenSim reads
    /// with the conversions of `40000`).
    V4,
}

/// The `Version` number of a document.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct DocumentVersion {
    pub number: u32,
    pub dialect: Dialect,
}

impl DocumentVersion {
    /// The dialect of a version number; `None` for numbers no OpenSim release wrote and for the
/// 4.0 development formats 30500–30516.
    pub fn from_number(number: u32) -> Option<Self> {
        let dialect = match number {
            20000..=29999 => Dialect::V2,
            30000..=30499 => Dialect::V3,
            30517..=49999 => Dialect::V4,
            _ => return None,
        };
        Some(DocumentVersion { number, dialect })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_ranges_map_to_dialects() {
        assert_eq!(DocumentVersion::from_number(20302).unwrap().dialect, Dialect::V2);
        assert_eq!(DocumentVersion::from_number(30000).unwrap().dialect, Dialect::V3);
        assert_eq!(DocumentVersion::from_number(40000).unwrap().dialect, Dialect::V4);
        assert_eq!(DocumentVersion::from_number(30517).unwrap().dialect, Dialect::V4);
        // 4.0 development formats (connectors, frames in a FrameSet, …).
        assert!(DocumentVersion::from_number(30501).is_none() && DocumentVersion::from_number(30516).is_none());
        assert!(DocumentVersion::from_number(10500).is_none());
        assert!(DocumentVersion::from_number(50000).is_none());
    }
}
