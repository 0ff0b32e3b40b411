//! `likeness view`: serves the avatar viewer page (`viewer/`, built with
//! npm) and the files it was given on 127.0.0.1, and prints the address.
//!
//! The server knows every URL it answers before it starts: the page's own
//! files (each regular file under the built `viewer/dist`) and one URL per
//! file given on the command line. A request is answered only when its path
//! is one of those strings exactly, so no path from a request ever reaches
//! the file system (no `..`, no percent-decoding). Requests whose `Host` is
//! not this server's own address are refused, so another site cannot read
//! the files through a DNS name rebound to 127.0.0.1.

use crate::CliResult;
use likeness::session::interchange::read_frames;
use std::collections::HashMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Ipv4Addr, SocketAddr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

/// How to build the page, said whenever it is missing.
const BUILD_HINT: &str = "npm --prefix viewer ci && npm --prefix viewer run build";

/// The page may load only from this server (its script, its style, the
/// files given) and from blobs it made itself: nothing from the network.
const CONTENT_SECURITY_POLICY: &str = "default-src 'self'; img-src 'self' blob: data:; \
     connect-src 'self' blob: data:; style-src 'self' 'unsafe-inline'; object-src 'none'; \
     base-uri 'none'; form-action 'none'; frame-ancestors 'none'";

/// The longest request head read (request line and headers).
const MAX_HEAD_BYTES: usize = 16 * 1024;

/// What `likeness view` was asked to show.
pub struct ViewArgs {
    /// The avatar to show (e.g. the personalized one `likeness avatar` wrote).
    pub avatar: PathBuf,
    /// The avatar before implanting, shown beside it.
    pub generic: Option<PathBuf>,
    /// A weight stream: Live Link Face CSV or `frames.csv` from `likeness export`.
    pub take: Option<PathBuf>,
    /// The port; 0 lets the system choose a free one.
    pub port: u16,
    /// The built page; default: `viewer/dist` in this repository.
    pub viewer_dir: Option<PathBuf>,
}

/// One URL the server answers, and the file behind it.
#[derive(Clone, Debug)]
struct Route {
    file: PathBuf,
    content_type: &'static str,
}

/// `likeness view`: checks the inputs, binds 127.0.0.1 and serves until
/// the process is stopped.
pub fn view_command(args: &ViewArgs) -> CliResult {
    let dist = args.viewer_dir.clone().unwrap_or_else(default_viewer_dir);
    let mut routes = page_routes(&dist)?;
    let mut query = Vec::new();
    // Left pane first: the generic avatar, then the one asked about.
    let avatars = match &args.generic {
        Some(generic) => vec![("generic", generic), ("avatar", &args.avatar)],
        None => vec![("avatar", &args.avatar)],
    };
    for ((key, path), param) in avatars.into_iter().zip(["a", "b"]) {
        check_glb(path)?;
        let url = file_url(key, path);
        query.push(format!("{param}={url}"));
        routes.insert(url, route_for(path));
    }
    if let Some(take) = &args.take {
        let frames = read_frames(take)?;
        let seconds = frames.last().map(|f| f.timestamp).unwrap_or(0.0);
        eprintln!(
            "take {}: {} frames, {seconds:.1} s",
            take.display(),
            frames.len()
        );
        let url = file_url("take", take);
        query.push(format!("take={url}"));
        routes.insert(url, route_for(take));
    }

    let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, args.port))
        .map_err(|e| format!("cannot listen on 127.0.0.1:{}: {e}", args.port))?;
    let address = listener.local_addr()?;
    let start = format!("/?{}", query.join("&"));
    println!("Likeness viewer: http://{address}{start}");
    eprintln!(
        "serving the page from {} on 127.0.0.1 only; Ctrl-C stops it",
        dist.display()
    );
    serve(listener, Arc::new(Site { routes, start }))
}

/// `viewer/dist` in the repository this binary was built from.
fn default_viewer_dir() -> PathBuf {
    let cli = Path::new(env!("CARGO_MANIFEST_DIR"));
    cli.parent().unwrap_or(cli).join("viewer/dist")
}

/// Every regular file under the built page, by URL path (`/viewer.js`);
/// an error that says how to build the page when there is none.
fn page_routes(dist: &Path) -> Result<HashMap<String, Route>, String> {
    if !dist.join("index.html").is_file() {
        let viewer = dist.parent().unwrap_or(dist);
        return Err(format!(
            "the viewer page is not built ({} has no index.html): run `{BUILD_HINT}` in {}",
            dist.display(),
            viewer.parent().unwrap_or(viewer).display()
        ));
    }
    let mut routes = HashMap::new();
    let mut folders = vec![dist.to_path_buf()];
    while let Some(folder) = folders.pop() {
        let entries =
            std::fs::read_dir(&folder).map_err(|e| format!("{}: {e}", folder.display()))?;
        for entry in entries {
            let entry = entry.map_err(|e| format!("{}: {e}", folder.display()))?;
            let (path, kind) = (entry.path(), entry.file_type());
            // Symbolic links are not followed: the build writes none.
            if kind.as_ref().is_ok_and(|k| k.is_dir()) {
                folders.push(path);
            } else if kind.as_ref().is_ok_and(|k| k.is_file()) {
                let relative = path.strip_prefix(dist).unwrap_or(&path);
                let parts: Vec<String> = relative
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                routes.insert(format!("/{}", parts.join("/")), route_for(&path));
            }
        }
    }
    Ok(routes)
}

/// The URL path of a given file: `/files/<key>/<its name, made URL-safe>`.
fn file_url(key: &str, path: &Path) -> String {
    let name: String = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_') {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("/files/{key}/{name}")
}

fn route_for(path: &Path) -> Route {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let content_type = match extension.as_str() {
        "html" => "text/html; charset=utf-8",
        "js" | "mjs" => "text/javascript; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        "json" | "map" => "application/json",
        "csv" => "text/csv; charset=utf-8",
        "glb" => "model/gltf-binary",
        "png" => "image/png",
        "svg" => "image/svg+xml",
        "ico" => "image/x-icon",
        _ => "application/octet-stream",
    };
    Route {
        file: path.to_path_buf(),
        content_type,
    }
}

/// A binary glTF 2.0 file: the page loads GLBs only (a `.gltf` would need
/// its buffers and images served too).
fn check_glb(path: &Path) -> Result<(), String> {
    let mut head = Vec::with_capacity(8);
    std::fs::File::open(path)
        .and_then(|f| f.take(8).read_to_end(&mut head))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    // Magic `glTF`, then version 2 as a little-endian u32.
    if head != b"glTF\x02\0\0\0" {
        return Err(format!(
            "{}: not a binary glTF 2.0 file (.glb); the viewer opens GLB files",
            path.display()
        ));
    }
    Ok(())
}

/// What the server answers.
struct Site {
    routes: HashMap<String, Route>,
    /// Where `/` leads: the page with the given files in its query.
    start: String,
}

/// Accepts connections for ever, one thread each.
fn serve(listener: TcpListener, site: Arc<Site>) -> CliResult {
    let own = listener.local_addr()?;
    for stream in listener.incoming() {
        let Ok(stream) = stream else { continue };
        let site = Arc::clone(&site);
        std::thread::spawn(move || {
            if let Err(e) = answer(stream, &site, own) {
                eprintln!("viewer connection: {e}");
            }
        });
    }
    Ok(())
}

/// Reads one request and answers it; the connection is then closed.
fn answer(stream: TcpStream, site: &Site, own: SocketAddr) -> std::io::Result<()> {
    stream.set_read_timeout(Some(Duration::from_secs(10)))?;
    stream.set_write_timeout(Some(Duration::from_secs(60)))?;
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut out = stream;
    let Some(head) = read_head(&mut reader)? else {
        return respond(&mut out, "400 Bad Request", "text/plain", b"bad request\n");
    };
    let mut lines = head.lines();
    let request_line = lines.next().unwrap_or_default();
    let mut words = request_line.split(' ');
    let (method, target) = (words.next().unwrap_or(""), words.next().unwrap_or(""));
    let host = lines
        .filter_map(|l| l.split_once(':'))
        .find(|(name, _)| name.trim().eq_ignore_ascii_case("host"))
        .map(|(_, value)| value.trim().to_string());
    let port = own.port();
    let own_host = host
        .as_deref()
        .is_some_and(|h| h == format!("127.0.0.1:{port}") || h == format!("localhost:{port}"));
    if !own_host {
        return respond(&mut out, "403 Forbidden", "text/plain", b"forbidden\n");
    }
    let head_only = match method {
        "GET" => false,
        "HEAD" => true,
        _ => {
            return respond(
                &mut out,
                "405 Method Not Allowed",
                "text/plain",
                b"method not allowed\n",
            );
        }
    };
    if target == "/" {
        let header = format!(
            "HTTP/1.1 302 Found\r\nLocation: {}\r\nContent-Length: 0\r\nConnection: close\r\n\r\n",
            site.start
        );
        return out.write_all(header.as_bytes());
    }
    let path = target.split_once('?').map_or(target, |(p, _)| p);
    let path = if path == "/" { "/index.html" } else { path };
    let Some(route) = site.routes.get(path) else {
        return respond(&mut out, "404 Not Found", "text/plain", b"not found\n");
    };
    let Ok(mut file) = std::fs::File::open(&route.file) else {
        return respond(&mut out, "404 Not Found", "text/plain", b"not found\n");
    };
    let length = file.metadata()?.len();
    let header = format!(
        "HTTP/1.1 200 OK\r\nContent-Type: {}\r\nContent-Length: {length}\r\n\
         Content-Security-Policy: {CONTENT_SECURITY_POLICY}\r\n\
         Cache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n",
        route.content_type
    );
    out.write_all(header.as_bytes())?;
    if !head_only {
        std::io::copy(&mut file, &mut out)?;
    }
    out.flush()
}

/// The request line and headers, up to the blank line; `None` when the
/// head is not text or longer than [`MAX_HEAD_BYTES`].
fn read_head(reader: &mut impl BufRead) -> std::io::Result<Option<String>> {
    let mut head = String::new();
    loop {
        let mut line = String::new();
        let read = reader
            .by_ref()
            .take((MAX_HEAD_BYTES - head.len()) as u64)
            .read_line(&mut line);
        match read {
            Ok(0) => return Ok(None),
            Ok(_) => {}
            Err(e) if e.kind() == std::io::ErrorKind::InvalidData => return Ok(None),
            Err(e) => return Err(e),
        }
        if line == "\r\n" || line == "\n" {
            return Ok(Some(head));
        }
        head.push_str(&line);
        if head.len() >= MAX_HEAD_BYTES {
            return Ok(None);
        }
    }
}

fn respond(
    out: &mut TcpStream,
    status: &str,
    content_type: &str,
    body: &[u8],
) -> std::io::Result<()> {
    let header = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        body.len()
    );
    out.write_all(header.as_bytes())?;
    out.write_all(body)?;
    out.flush()
}
