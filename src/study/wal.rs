//! Whether the write-ahead log beside a cache belongs to it, read before SQLite opens the
//! file. SQLite replays any well-formed `-wal` file into the database it finds it beside, and
//! its last connection checkpoints it into the file: a log of another database (copied with
//! the cache, or left by a crashed process of another file) would overwrite the cache's pages.
//!
//! The log's format (<https://www.sqlite.org/fileformat2.html#walformat>): a 32-byte header
//! (magic, format version, page size, checkpoint sequence, two salts, a checksum), then frames
//! of a 24-byte header (page number, database size in pages after a commit or 0, the salts, a
//! cumulative checksum) and one page. A frame counts while its salts are the header's and its
//! checksum continues the chain; SQLite ignores the rest.
//!
//! A log that belongs to the file passes both checks below, since a cache never shrinks (no
//! `VACUUM`, no auto-vacuum): its last commit leaves the database at least as large as the
//! file, and its page size is the file's.

use std::io::Read;
use std::path::{Path, PathBuf};

/// Why a log does not belong to its database.
#[derive(Debug, Clone, PartialEq)]
pub enum Mismatch {
    /// The log's pages are not the file's size.
    PageSize { wal: u32, db: u32 },
    /// The log's last commit leaves fewer pages than the file already has.
    Shrinks { wal_pages: u32, db_pages: u64 },
    /// The log's first page (the database header) names another application.
    Application { found: i32 },
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Mismatch::PageSize { wal, db } => {
                write!(f, "its pages are {wal} bytes, the cache's {db}")
            }
            Mismatch::Shrinks {
                wal_pages,
                db_pages,
            } => write!(
                f,
                "it describes a database of {wal_pages} pages, the cache has {db_pages}"
            ),
            Mismatch::Application { found } => {
                write!(
                    f,
                    "it holds the header of another application's database ({found:#x})"
                )
            }
        }
    }
}

/// The log beside `db`.
pub fn wal_path(db: &Path) -> PathBuf {
    let mut p = db.as_os_str().to_owned();
    p.push("-wal");
    PathBuf::from(p)
}

/// Checks the log beside `db` (none, an empty one or one SQLite would ignore passes) against
/// `db`'s header; `app` is the application id a first page must carry. I/O errors pass: the
/// open that follows reports them.
pub fn check(db: &Path, app: i32) -> Result<(), Mismatch> {
    let Some(page_size) = db_page_size(db) else {
        return Ok(());
    };
    let Ok(mut f) = std::fs::File::open(wal_path(db)) else {
        return Ok(());
    };
    let mut log = Vec::new();
    if f.read_to_end(&mut log).is_err() {
        return Ok(());
    }
    let Some(header) = Header::read(&log) else {
        return Ok(());
    };
    if header.page_size != page_size {
        return Err(Mismatch::PageSize {
            wal: header.page_size,
            db: page_size,
        });
    }
    let Some(last) = last_commit(&log, &header) else {
        return Ok(());
    };
    let db_pages = std::fs::metadata(db).map_or(0, |m| m.len()) / u64::from(page_size);
    if u64::from(last.pages) < db_pages {
        return Err(Mismatch::Shrinks {
            wal_pages: last.pages,
            db_pages,
        });
    }
    match last.first_page_app {
        Some(found) if found != app => Err(Mismatch::Application { found }),
        _ => Ok(()),
    }
}

/// The page size a database file's header gives (bytes 16–17, big-endian; 1 means 65536).
fn db_page_size(db: &Path) -> Option<u32> {
    let mut head = [0u8; 100];
    std::fs::File::open(db).ok()?.read_exact(&mut head).ok()?;
    match u16::from_be_bytes([head[16], head[17]]) {
        1 => Some(65536),
        n => Some(u32::from(n)),
    }
}

struct Header {
    big_endian: bool,
    page_size: u32,
    salt: [u32; 2],
    checksum: [u32; 2],
}

fn be(b: &[u8], at: usize) -> u32 {
    u32::from_be_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

impl Header {
    /// The header, if well formed (magic, version, a power-of-two page size, its checksum).
    fn read(log: &[u8]) -> Option<Header> {
        if log.len() < 32 {
            return None;
        }
        let big_endian = match be(log, 0) {
            0x377f_0682 => false,
            0x377f_0683 => true,
            _ => return None,
        };
        let page_size = be(log, 8);
        let ok_size = (512..=65536).contains(&page_size) && page_size.is_power_of_two();
        if be(log, 4) != 3_007_000 || !ok_size {
            return None;
        }
        let checksum = [be(log, 24), be(log, 28)];
        if sum(big_endian, [0, 0], &log[..24]) != checksum {
            return None;
        }
        Some(Header {
            big_endian,
            page_size,
            salt: [be(log, 16), be(log, 20)],
            checksum,
        })
    }
}

/// SQLite's log checksum (wal.c, `walChecksumBytes`): pairs of 32-bit words in the log's
/// byte order, summed with wrapping arithmetic into the running pair `s`.
fn sum(big_endian: bool, mut s: [u32; 2], bytes: &[u8]) -> [u32; 2] {
    let word = |w: &[u8]| {
        let a = [w[0], w[1], w[2], w[3]];
        if big_endian {
            u32::from_be_bytes(a)
        } else {
            u32::from_le_bytes(a)
        }
    };
    for pair in bytes.chunks_exact(8) {
        s[0] = s[0].wrapping_add(word(&pair[..4])).wrapping_add(s[1]);
        s[1] = s[1].wrapping_add(word(&pair[4..])).wrapping_add(s[0]);
    }
    s
}

/// What the log's last valid commit says.
struct Commit {
    /// The database size in pages after it.
    pages: u32,
    /// The application id in the newest first page committed up to it, if the log has one.
    first_page_app: Option<i32>,
}

/// Walks the valid frames and returns the last commit, if any.
fn last_commit(log: &[u8], h: &Header) -> Option<Commit> {
    let frame = 24 + h.page_size as usize;
    let mut s = h.checksum;
    let mut app = None;
    let mut last = None;
    for f in log[32..].chunks_exact(frame) {
        if [be(f, 8), be(f, 12)] != h.salt {
            break;
        }
        s = sum(h.big_endian, s, &f[..8]);
        s = sum(h.big_endian, s, &f[24..]);
        if s != [be(f, 16), be(f, 20)] {
            break;
        }
        if be(f, 0) == 1 {
            app = Some(be(f, 24 + 68) as i32);
        }
        let pages = be(f, 4);
        if pages != 0 {
            last = Some(Commit {
                pages,
                first_page_app: app,
            });
        }
    }
    last
}
