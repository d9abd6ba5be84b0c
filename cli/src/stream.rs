//! `tessellate` without `--check-watertight`: the result goes to disk chunk
//! by chunk ([`tessellate::Session::run_chunked`], [`obj::ObjStream`](ObjStream)), so
//! peak memory is one chunk (about 100 MB of samples) whatever the level, and
//! into `OUT.partial` renamed to `OUT` at the end, so a failed run leaves no
//! half-written file (a special file such as `/dev/null` is written
//! directly). The bytes are the non-streamed OBJ's. `--adaptive` writes a
//! triangle soup ([`Output::write_soup`]), streamed the same way.
//!
//! `--out` ending in `.glb` or `.ply` writes a welded binary mesh instead
//! ([`export::MeshStream`](MeshStream), [`Output::write_mesh`]), streamed the same way
//! (its vertex and index data through two temporary files beside the
//! output, or in the temporary directory for a special file).

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::time::Instant;

use tessgen_runtime::export::{Format, MeshStream};
use tessgen_runtime::obj::ObjStream;
use tessgen_runtime::tessellate::{self, ChunkError, Output};

/// Counts for the summary line.
#[derive(Default)]
pub(crate) struct Written {
    pub faces: usize,
    pub samples: usize,
    /// `(patches, vertices, triangles)` of a non-grid result (polygon
    /// grids, captured triangles), summed over its chunks.
    pub other: Option<(usize, usize, usize)>,
    /// Triangles of a soup (`soup`).
    pub triangles: usize,
    pub ms: f64,
}

/// Tessellate `validated` into `out` as OBJ, streamed: grids in the grid
/// layout, or with `soup` every chunk as a triangle soup.
pub(crate) fn write_streamed(
    validated: &tessellate::Validated<'_>,
    mesh_path: &Path,
    out: &Path,
    soup: bool,
) -> Result<Written, String> {
    let direct = std::fs::metadata(out).is_ok_and(|m| !m.is_file());
    let target: PathBuf = if direct {
        out.to_path_buf()
    } else {
        let mut name = out.as_os_str().to_owned();
        name.push(".partial");
        PathBuf::from(name)
    };
    let io = |e: std::io::Error| format!("{}: {e}", target.display());
    let format = Format::of(out);
    let mut mesh = match format {
        Format::Obj => None,
        _ => Some(MeshStream::new(format, &scratch(&target, direct)).map_err(io)?),
    };
    let file = File::create(&target).map_err(io)?;
    let mut stream = ObjStream::new(BufWriter::with_capacity(1 << 20, file));
    let mut written = Written::default();
    let start = Instant::now();
    let result = tessellate::Session::new().run_chunked(validated, 0, |chunk| {
        if let Some(m) = mesh.as_mut() {
            count(&mut written, chunk);
            let before = m.triangle_count();
            chunk.write_mesh(m)?;
            written.triangles += (m.triangle_count() - before) as usize;
            Ok(())
        } else if soup {
            written.triangles += chunk.write_soup(&mut stream)?;
            Ok(())
        } else {
            // Polygon grids come window by window, captured triangles
            // whole: counted over every chunk, written patch by patch.
            count(&mut written, chunk);
            chunk.write_obj(&mut stream)
        }
    });
    written.ms = start.elapsed().as_secs_f64() * 1e3;
    let finished = result.map_err(|e| match e {
        ChunkError::Tess(e) => format!("{}: {e}", mesh_path.display()),
        ChunkError::Sink(e) => format!("{}: {e}", target.display()),
    });
    let flushed = finished.and_then(|()| match mesh {
        Some(m) => {
            let mut w = stream.finish().map_err(io)?;
            m.finish(&mut w).map_err(io)
        }
        None => stream.finish().map(|_| ()).map_err(io),
    });
    match flushed {
        Ok(_) if direct => Ok(written),
        Ok(_) => std::fs::rename(&target, out)
            .map(|()| written)
            .map_err(|e| format!("{}: {e}", out.display())),
        Err(e) => {
            if !direct {
                let _ = std::fs::remove_file(&target);
            }
            Err(e)
        }
    }
}

/// Grid counts of a chunk (what the summary line reports).
fn count(written: &mut Written, chunk: &Output) {
    match chunk {
        Output::Grid(t) => {
            written.faces += t.faces;
            written.samples += t.positions.len();
        }
        Output::Instanced(_) => {}
        other => {
            let (patches, vertices, triangles) = other.counts();
            let sum = written.other.get_or_insert((0, 0, 0));
            (sum.0, sum.1, sum.2) = (sum.0 + patches, sum.1 + vertices, sum.2 + triangles);
        }
    }
}

/// Where a binary mesh's temporary vertex and index files go: beside the
/// partial output, or for a special file (`/dev/null`) in the temporary
/// directory.
fn scratch(target: &Path, direct: bool) -> PathBuf {
    if direct {
        std::env::temp_dir().join(format!("tessgen-{}-mesh", std::process::id()))
    } else {
        target.to_path_buf()
    }
}

/// The whole result `out` into `path` in the format its extension names:
/// OBJ ([`Output::to_obj`], or with `soup` the triangle soup), or a welded
/// `.glb` / `.ply` ([`Output::write_mesh`]; then the triangles it holds:
/// the weld leaves out the collapsed ones).
pub(crate) fn write_whole(out: &Output, path: &Path, soup: bool) -> Result<Option<u64>, String> {
    let direct = std::fs::metadata(path).is_ok_and(|m| !m.is_file());
    let r = write_whole_into(out, path, soup, direct);
    if r.is_err() && !direct {
        // No half-written file is left behind.
        let _ = std::fs::remove_file(path);
    }
    r
}

fn write_whole_into(
    out: &Output,
    path: &Path,
    soup: bool,
    direct: bool,
) -> Result<Option<u64>, String> {
    let io = |e: std::io::Error| format!("{}: {e}", path.display());
    let format = Format::of(path);
    let file = File::create(path).map_err(io)?;
    let mut w = BufWriter::with_capacity(1 << 20, file);
    match format {
        Format::Obj if soup => {
            let mut obj = ObjStream::new(w);
            out.write_soup(&mut obj).map_err(io)?;
            obj.finish().map(|_| None).map_err(io)
        }
        Format::Obj => {
            use std::io::Write as _;
            w.write_all(out.to_obj().as_bytes()).map_err(io)?;
            w.flush().map(|()| None).map_err(io)
        }
        _ => {
            let mut mesh = MeshStream::new(format, &scratch(path, direct)).map_err(io)?;
            out.write_mesh(&mut mesh).map_err(io)?;
            let triangles = mesh.triangle_count();
            mesh.finish(&mut w).map(|()| Some(triangles)).map_err(io)
        }
    }
}
