//! The files of a study (`studies::StudyKind`): which, by name, and how its
//! output is written into them. The study job (`run::study_job`) stages the
//! folder with these names and calls [`StudyFiles::write`] at the end.

use super::Provenance;
use crate::studies::compare::{CompareStudy, Row};
use crate::studies::effective_area::AreaResult;
use crate::studies::fit_study::{FitOutput, FitStudy};
use crate::studies::focus::{FocusScan, FocusStudy};
use crate::studies::psf::{PsfGrid, PsfLibrary};
use crate::studies::systematics::{Systematics, SystematicsStudy};
use crate::studies::{effective_area::AreaSweep, StudyKind};
use std::path::Path;

/// A study's files.
pub trait StudyFiles: StudyKind {
    /// The files it writes, besides its record.
    fn files(&self) -> Vec<String>;

    /// Writes `output` into `dir`.
    fn write(
        &self,
        dir: &Path,
        output: &Self::Output,
        provenance: &Provenance,
    ) -> std::io::Result<()>;

    /// The provenance as the study states it (focus: without the variable it
    /// sweeps); as the job made it by default.
    fn provenance(&self, made: Provenance) -> Provenance {
        made
    }
}

impl StudyFiles for AreaSweep {
    fn files(&self) -> Vec<String> {
        super::effective_area_files(&self.angles_arcmin, &self.energies)
    }

    fn write(
        &self,
        dir: &Path,
        output: &AreaResult,
        provenance: &Provenance,
    ) -> std::io::Result<()> {
        super::write_effective_area(dir, output, self.radius_mm, provenance).map(|_| ())
    }
}

impl StudyFiles for PsfGrid {
    fn files(&self) -> Vec<String> {
        super::PSF_FILES.iter().map(|f| f.to_string()).collect()
    }

    fn write(
        &self,
        dir: &Path,
        output: &PsfLibrary,
        provenance: &Provenance,
    ) -> std::io::Result<()> {
        super::write_psf_library(dir, output, self, provenance)
    }
}

impl StudyFiles for SystematicsStudy<'_> {
    fn files(&self) -> Vec<String> {
        super::SYSTEMATICS_FILES
            .all()
            .iter()
            .map(|f| f.to_string())
            .collect()
    }

    fn write(
        &self,
        dir: &Path,
        output: &Systematics,
        provenance: &Provenance,
    ) -> std::io::Result<()> {
        super::write_systematics(dir, output, &self.scene_name, provenance)
    }
}

impl StudyFiles for FocusStudy<'_> {
    fn files(&self) -> Vec<String> {
        super::FOCUS_FILES.iter().map(|f| f.to_string()).collect()
    }

    fn write(
        &self,
        dir: &Path,
        output: &FocusScan,
        provenance: &Provenance,
    ) -> std::io::Result<()> {
        let range = (self.sweep.from, self.sweep.to);
        super::write_focus(dir, output, &self.var, range, provenance).map(|_| ())
    }

    /// The scene as the user gave it: the swept variable is in focus.csv.
    fn provenance(&self, mut made: Provenance) -> Provenance {
        made.variables.remove(&self.var);
        made
    }
}

impl StudyFiles for FitStudy<'_> {
    fn files(&self) -> Vec<String> {
        super::FIT_FILES.iter().map(|f| f.to_string()).collect()
    }

    fn write(
        &self,
        dir: &Path,
        output: &FitOutput,
        provenance: &Provenance,
    ) -> std::io::Result<()> {
        super::write_fit(dir, &super::FitReport::of(self, output), provenance).map(|_| ())
    }
}

impl StudyFiles for CompareStudy<'_> {
    fn files(&self) -> Vec<String> {
        super::COMPARE_FILES.iter().map(|f| f.to_string()).collect()
    }

    fn write(&self, dir: &Path, rows: &Vec<Row>, provenance: &Provenance) -> std::io::Result<()> {
        super::write_compare(dir, rows, provenance).map(|_| ())
    }
}
