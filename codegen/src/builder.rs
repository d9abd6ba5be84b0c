//! The build-time API: pick schemes and targets, get files.
//!
//! ```no_run
//! // build.rs
//! let out = std::env::var("OUT_DIR").unwrap();
//! tessgen_codegen::Builder::new()
//!     .builtin_schemes()
//!     .target(tessgen_codegen::Target::Rust)
//!     .out_dir(out)
//!     .write()
//!     .expect("tessgen");
//! ```

use crate::backend::{self, Target};
pub use crate::error::BuildError;
use crate::front::scheme::Scheme;
pub use crate::outdir::GeneratedFile;
use crate::plan::Plan;
use crate::table::{StencilTable, DEFAULT_MAX_VALENCE};
use std::path::{Path, PathBuf};

/// Scheme source text and where it came from (for error messages).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SchemeSource {
    pub origin: String,
    pub text: String,
}

impl SchemeSource {
    pub fn new(origin: impl Into<String>, text: impl Into<String>) -> Self {
        SchemeSource {
            origin: origin.into(),
            text: text.into(),
        }
    }
    /// Read a `.tess` file.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self, BuildError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| BuildError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Ok(SchemeSource::new(path.display().to_string(), text))
    }
    /// Parse and check.
    pub fn compile(&self, max_valence: u32) -> Result<Scheme, BuildError> {
        Scheme::from_source(&self.text, max_valence).map_err(|error| BuildError::Scheme {
            origin: self.origin.clone(),
            error,
        })
    }
}

/// The built-in schemes, declared in `codegen/schemes/*.tess` and nowhere else.
pub fn builtin_schemes() -> Vec<SchemeSource> {
    vec![
        SchemeSource::new(
            "codegen/schemes/regular.tess",
            include_str!("../schemes/regular.tess"),
        ),
        SchemeSource::new(
            "codegen/schemes/pccm.tess",
            include_str!("../schemes/pccm.tess"),
        ),
        SchemeSource::new(
            "codegen/schemes/acc.tess",
            include_str!("../schemes/acc.tess"),
        ),
        SchemeSource::new(
            "codegen/schemes/gregory.tess",
            include_str!("../schemes/gregory.tess"),
        ),
        SchemeSource::new(
            "codegen/schemes/gregory_osd.tess",
            include_str!("../schemes/gregory_osd.tess"),
        ),
        SchemeSource::new(
            "codegen/schemes/pn.tess",
            include_str!("../schemes/pn.tess"),
        ),
        SchemeSource::new(
            "codegen/schemes/stpn.tess",
            include_str!("../schemes/stpn.tess"),
        ),
        SchemeSource::new(
            "codegen/schemes/phong.tess",
            include_str!("../schemes/phong.tess"),
        ),
        // Last, so the other schemes' table rows and generated code stay
        // where they were.
        SchemeSource::new(
            "codegen/schemes/g1cc.tess",
            include_str!("../schemes/g1cc.tess"),
        ),
    ]
}

/// Everything a build produced.
#[derive(Clone, Debug)]
pub struct Output {
    pub schemes: Vec<Scheme>,
    pub table: StencilTable,
    pub plan: Plan,
    pub files: Vec<GeneratedFile>,
}

impl Output {
    pub fn file(&self, path: &str) -> Option<&GeneratedFile> {
        self.files.iter().find(|f| f.path == path)
    }
}

/// Configures and runs code generation.
#[derive(Clone, Debug)]
pub struct Builder {
    schemes: Vec<SchemeSource>,
    targets: Vec<Target>,
    max_valence: u32,
    out_dir: Option<PathBuf>,
    command: String,
}

impl Default for Builder {
    fn default() -> Self {
        Builder {
            schemes: Vec::new(),
            targets: Vec::new(),
            max_valence: DEFAULT_MAX_VALENCE,
            out_dir: None,
            command: "tessgen_codegen::Builder (build.rs)".into(),
        }
    }
}

impl Builder {
    pub fn new() -> Self {
        Self::default()
    }
    /// Add the built-in `regular` and `pccm` schemes.
    pub fn builtin_schemes(mut self) -> Self {
        self.schemes.extend(builtin_schemes());
        self
    }
    pub fn scheme(mut self, s: SchemeSource) -> Self {
        self.schemes.push(s);
        self
    }
    pub fn target(mut self, t: Target) -> Self {
        if !self.targets.contains(&t) {
            self.targets.push(t);
        }
        self
    }
    /// All targets.
    pub fn all_targets(mut self) -> Self {
        self.targets = Target::ALL.to_vec();
        self
    }
    /// Largest valence of the stencil table (default 32).
    pub fn max_valence(mut self, n: u32) -> Self {
        self.max_valence = n;
        self
    }
    pub fn out_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.out_dir = Some(dir.into());
        self
    }
    /// The command recorded in every file's header.
    pub fn command(mut self, c: impl Into<String>) -> Self {
        self.command = c.into();
        self
    }

    /// Compile everything in memory.
    pub fn compile(&self) -> Result<Output, BuildError> {
        if self.schemes.is_empty() {
            return Err(BuildError::NoScheme);
        }
        let mut schemes: Vec<Scheme> = Vec::new();
        for src in &self.schemes {
            let s = src.compile(self.max_valence)?;
            if let Some(j) = schemes.iter().position(|t| t.name == s.name) {
                return Err(BuildError::DuplicateScheme {
                    name: s.name,
                    origin: src.origin.clone(),
                    first: self.schemes[j].origin.clone(),
                });
            }
            schemes.push(s);
        }
        let table = StencilTable::build(&schemes, self.max_valence);
        let plan = crate::lower::plan(&schemes, &table);
        let mut files = vec![
            GeneratedFile {
                path: "table/stencils.f32".into(),
                contents: table.to_le_bytes(),
            },
            GeneratedFile {
                path: "table/stencils.json".into(),
                contents: table.manifest_json().into_bytes(),
            },
        ];
        for t in &self.targets {
            match t {
                Target::Rust => files.push(GeneratedFile {
                    path: "rust/tessgen.rs".into(),
                    contents: backend::rust::write(&plan, &self.command).into_bytes(),
                }),
                Target::Wgsl => files.extend(backend::wgsl::write(&plan, &self.command)),
                Target::Glsl => files.extend(backend::glsl::write(&plan, &self.command)),
                Target::Hlsl => files.extend(backend::hlsl::write(&plan, &self.command)),
            }
        }
        if self.targets.iter().any(|t| *t != Target::Rust) {
            files.push(GeneratedFile {
                path: "README.md".into(),
                contents: backend::docs::readme(&plan, &table, &self.command).into_bytes(),
            });
        }
        Ok(Output {
            schemes,
            table,
            plan,
            files,
        })
    }

    /// Compile and write into the output directory; returns every generated
    /// path. Files whose contents are already right are left untouched, so
    /// build scripts don't retrigger.
    pub fn write(&self) -> Result<Vec<PathBuf>, BuildError> {
        let dir = self.out_dir.clone().ok_or(BuildError::NoOutDir)?;
        let out = self.compile()?;
        crate::outdir::write(&dir, &out.files)?;
        Ok(out.files.iter().map(|f| dir.join(&f.path)).collect())
    }
}
