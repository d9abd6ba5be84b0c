//! `tessellate` without `--check-watertight`: the result goes to disk chunk
//! by chunk ([`tessellate::Session::run_chunked`], [`obj::ObjStream`]), so
//! peak memory is one chunk (about 100 MB of samples) whatever the level, and
//! into `OUT.partial` renamed to `OUT` at the end, so a failed run leaves no
//! half-written file (a special file such as `/dev/null` is written
//! directly). The bytes are the non-streamed OBJ's. `--adaptive` writes a
//! triangle soup ([`Output::write_soup`]), streamed the same way.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::time::Instant;

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
    let file = File::create(&target).map_err(io)?;
    let mut stream = ObjStream::new(BufWriter::with_capacity(1 << 20, file));
    let mut written = Written::default();
    let start = Instant::now();
    let result = tessellate::Session::new().run_chunked(validated, 0, |chunk| match chunk {
        soupy if soup => {
            written.triangles += soupy.write_soup(&mut stream)?;
            Ok(())
        }
        Output::Grid(t) => {
            written.faces += t.faces;
            written.samples += t.positions.len();
            stream.write(t)
        }
        // Polygon grids come window by window, captured triangles whole:
        // counted over every chunk, written patch by patch.
        other => {
            let (patches, vertices, triangles) = other.counts();
            let sum = written.other.get_or_insert((0, 0, 0));
            (sum.0, sum.1, sum.2) = (sum.0 + patches, sum.1 + vertices, sum.2 + triangles);
            other.write_obj(&mut stream)
        }
    });
    written.ms = start.elapsed().as_secs_f64() * 1e3;
    let finished = result.map_err(|e| match e {
        ChunkError::Tess(e) => format!("{}: {e}", mesh_path.display()),
        ChunkError::Sink(e) => format!("{}: {e}", target.display()),
    });
    let flushed = finished.and_then(|()| stream.finish().map_err(io));
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
