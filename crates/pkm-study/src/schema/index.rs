//! The names of the indices a grid study evaluates (a leaf of the module graph: errors name
//! them too).

use serde::{Deserialize, Serialize};

/// An index a grid study can ask for.
///
/// | index | meaning | unit | mechanisms |
/// |---|---|---|---|
/// | `volume` | workspace volume W over the study's points | m³ | all |
/// | `eta` | η = ∫ 1/κ dW | m³ | all |
/// | `gci` | GCI = η / W (Gosselin & Angeles) | – | all |
/// | `eta1` | mean 1/κ over the y–z cross-section (Miller 2004 eq. 1) | – | linear_delta |
/// | `eta2` | space utilisation (Miller 2004 eq. 2) | – | linear_delta |
/// | `area` | cross-section area A_W / Y_R² | – | linear_delta |
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum IndexName {
    /// Workspace volume (m³).
    Volume,
    /// η = ∫ 1/κ dW (m³).
    Eta,
    /// η / W.
    Gci,
    /// Linear Delta manipulability, eq. 1.
    Eta1,
    /// Linear Delta space utilisation, eq. 2.
    Eta2,
    /// Linear Delta cross-section area over Y_R².
    Area,
}

impl IndexName {
    /// The name in study files and CSV headers.
    pub fn key(self) -> &'static str {
        match self {
            Self::Volume => "volume",
            Self::Eta => "eta",
            Self::Gci => "gci",
            Self::Eta1 => "eta1",
            Self::Eta2 => "eta2",
            Self::Area => "area",
        }
    }

    /// Whether it is estimated over the study's workspace points.
    pub fn needs_points(self) -> bool {
        matches!(self, Self::Volume | Self::Eta | Self::Gci)
    }
}
