//! `likeness view`: the server answers only the page's own files and the
//! files it was given, on 127.0.0.1; a missing page says how to build it.
//! Also keeps the viewer's committed take in step with the simulated
//! session it was cut from.
//!
//! These tests need no npm: they serve a small stand-in page through
//! `--viewer-dir`. The page itself is tested in a browser by
//! `viewer/run-tests.sh`.

use likeness::session::interchange::read_frames;
use likeness_tests::committed;
use likeness_tests::live_link::live_link_csv;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

mod common;

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    common::scratch("view", name)
}

/// A stand-in for `viewer/dist`, a GLB header, and a file beside them
/// that must never be served.
fn fixture(dir: &Path) -> (PathBuf, PathBuf) {
    let dist = dir.join("dist");
    std::fs::create_dir_all(dist.join("assets")).unwrap();
    std::fs::write(
        dist.join("index.html"),
        "<!doctype html><title>viewer</title>",
    )
    .unwrap();
    std::fs::write(dist.join("viewer.js"), "console.log('viewer');").unwrap();
    std::fs::write(dist.join("assets/style.css"), "body{}").unwrap();
    std::fs::write(dir.join("secret.txt"), "secret").unwrap();
    let glb = dir.join("my avatar.glb");
    let mut bytes = b"glTF".to_vec();
    bytes.extend_from_slice(&2u32.to_le_bytes());
    bytes.extend_from_slice(&[0; 12]);
    std::fs::write(&glb, &bytes).unwrap();
    (dist, glb)
}

/// A running `likeness view`, stopped when dropped.
struct Server {
    child: Child,
    /// The address it printed.
    url: String,
    /// `127.0.0.1:PORT`.
    host: String,
}

impl Server {
    fn start(args: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_likeness"))
            .arg("view")
            .args(args)
            .args(["--port", "0"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("the likeness binary runs");
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let url = line
            .trim()
            .strip_prefix("Likeness viewer: ")
            .unwrap_or_else(|| panic!("no address printed: {line:?}"))
            .to_string();
        let host = url
            .strip_prefix("http://")
            .and_then(|rest| rest.split('/').next())
            .unwrap()
            .to_string();
        Server { child, url, host }
    }

    /// Sends `request` (a request line) with this server's Host header and
    /// returns the status code and body.
    fn get(&self, request_line: &str) -> (u16, Vec<u8>) {
        self.raw(&format!("{request_line}\r\nHost: {}\r\n\r\n", self.host))
    }

    fn raw(&self, request: &str) -> (u16, Vec<u8>) {
        let mut stream = TcpStream::connect(&self.host).unwrap();
        stream.write_all(request.as_bytes()).unwrap();
        let mut response = Vec::new();
        stream.read_to_end(&mut response).unwrap();
        let split = response
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .expect("a response head");
        let head = String::from_utf8_lossy(&response[..split]).into_owned();
        let status = head.split(' ').nth(1).unwrap().parse().unwrap();
        (status, response[split + 4..].to_vec())
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn serves_the_page_and_the_given_files_on_127_0_0_1() {
    let dir = scratch("serve");
    let (dist, glb) = fixture(&dir);
    let server = Server::start(&[
        glb.to_str().unwrap(),
        "--viewer-dir",
        dist.to_str().unwrap(),
    ]);
    assert!(
        server.url.starts_with("http://127.0.0.1:"),
        "{}",
        server.url
    );
    assert!(
        server.url.ends_with("/?a=/files/avatar/my_avatar.glb"),
        "{}",
        server.url
    );

    let (status, body) = server.get("GET /index.html HTTP/1.1");
    assert_eq!(
        (status, body.as_slice()),
        (200, b"<!doctype html><title>viewer</title>".as_slice())
    );
    assert_eq!(server.get("GET /viewer.js HTTP/1.1").0, 200);
    assert_eq!(server.get("GET /assets/style.css?v=1 HTTP/1.1").0, 200);
    let (status, body) = server.get("GET /files/avatar/my_avatar.glb HTTP/1.1");
    assert_eq!(status, 200);
    assert_eq!(body, std::fs::read(&glb).unwrap());
    let (status, body) = server.get("HEAD /files/avatar/my_avatar.glb HTTP/1.1");
    assert_eq!((status, body.len()), (200, 0));
    // `/` leads to the page with the files in its query.
    assert_eq!(server.get("GET / HTTP/1.1").0, 302);
}

#[test]
fn no_path_leaves_the_page_and_the_given_files() {
    let dir = scratch("traversal");
    let (dist, glb) = fixture(&dir);
    let server = Server::start(&[
        glb.to_str().unwrap(),
        "--viewer-dir",
        dist.to_str().unwrap(),
    ]);
    for target in [
        "/../secret.txt",
        "/assets/../../secret.txt",
        "/files/avatar/../../secret.txt",
        "/files/avatar/..%2f..%2fsecret.txt",
        "/%2e%2e/secret.txt",
        "/%2E%2E%2Fsecret.txt",
        "/..\\secret.txt",
        "//secret.txt",
        "/files/avatar/secret.txt",
        "/files/avatar/",
        "/files/take/my_avatar.glb",
        "/assets",
        "/assets/",
        &format!("{}/secret.txt", dir.display()),
        &format!("http://{}/../secret.txt", server.host),
        "/etc/passwd",
    ] {
        let (status, body) = server.get(&format!("GET {target} HTTP/1.1"));
        assert_eq!(status, 404, "{target} answered {status}");
        assert!(
            !String::from_utf8_lossy(&body).contains("secret"),
            "{target}"
        );
    }
    // Only GET and HEAD, only for this server's own host name, and a
    // request head must end.
    assert_eq!(server.get("POST /index.html HTTP/1.1").0, 405);
    let rebound = "GET /index.html HTTP/1.1\r\nHost: attacker.example\r\n\r\n";
    assert_eq!(server.raw(rebound).0, 403);
    let no_host = "GET /index.html HTTP/1.1\r\n\r\n";
    assert_eq!(server.raw(no_host).0, 403);
    let localhost = format!(
        "GET /index.html HTTP/1.1\r\nHost: localhost:{}\r\n\r\n",
        server.host.split(':').nth(1).unwrap()
    );
    assert_eq!(server.raw(&localhost).0, 200);
}

#[test]
fn the_generic_avatar_and_a_take_are_served_beside_it() {
    let dir = scratch("both");
    let (dist, glb) = fixture(&dir);
    let generic = dir.join("generic.glb");
    std::fs::copy(&glb, &generic).unwrap();
    let take = committed_take_path();
    let server = Server::start(&[
        glb.to_str().unwrap(),
        "--generic",
        generic.to_str().unwrap(),
        "--take",
        take.to_str().unwrap(),
        "--viewer-dir",
        dist.to_str().unwrap(),
    ]);
    assert!(
        server.url.ends_with(
            "/?a=/files/generic/generic.glb&b=/files/avatar/my_avatar.glb\
             &take=/files/take/subject-1-take.csv"
        ),
        "{}",
        server.url
    );
    let (status, body) = server.get("GET /files/take/subject-1-take.csv HTTP/1.1");
    assert_eq!(status, 200);
    assert_eq!(body, std::fs::read(&take).unwrap());
    assert_eq!(server.get("GET /files/generic/generic.glb HTTP/1.1").0, 200);
}

fn likeness_view(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_likeness"))
        .arg("view")
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_missing_page_says_how_to_build_it() {
    let dir = scratch("unbuilt");
    let (_, glb) = fixture(&dir);
    let missing = dir.join("viewer/dist");
    let (ok, stderr) = likeness_view(&[
        glb.to_str().unwrap(),
        "--viewer-dir",
        missing.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(stderr.contains("the viewer page is not built"), "{stderr}");
    assert!(
        stderr.contains("npm --prefix viewer ci && npm --prefix viewer run build"),
        "{stderr}"
    );
}

#[test]
fn bad_inputs_are_clear_errors() {
    let dir = scratch("bad");
    let (dist, glb) = fixture(&dir);
    let dist = dist.to_str().unwrap();
    let not_glb = dir.join("secret.txt");
    let (ok, stderr) = likeness_view(&[not_glb.to_str().unwrap(), "--viewer-dir", dist]);
    assert!(!ok);
    assert!(
        stderr.contains("secret.txt: not a binary glTF 2.0 file"),
        "{stderr}"
    );
    let (ok, stderr) = likeness_view(&["missing.glb", "--viewer-dir", dist]);
    assert!(!ok);
    assert!(stderr.contains("missing.glb"), "{stderr}");
    let bad_take = dir.join("take.csv");
    std::fs::write(&bad_take, "Timecode,BlendShapeCount,EyeBlinkLeft\n").unwrap();
    let (ok, stderr) = likeness_view(&[
        glb.to_str().unwrap(),
        "--take",
        bad_take.to_str().unwrap(),
        "--viewer-dir",
        dist,
    ]);
    assert!(!ok);
    assert!(stderr.contains("take.csv"), "{stderr}");
}

/// The take the viewer's browser test plays.
fn committed_take_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../viewer/tests/fixtures/subject-1-take.csv")
}

/// Frames of subject 1's stream in the committed take: 5 s at 60 fps
/// around the cheekPuff, jawOpen and mouthClose prompts.
const TAKE_FRAMES: std::ops::Range<usize> = 2600..2900;

/// The committed take is simulated subject 1's stream, cut and written as
/// Live Link Face writes it; `LIKENESS_WRITE_VIEWER_TAKE=1` rewrites it.
#[test]
fn the_viewer_take_is_simulated_subject_1s_stream() {
    let session = committed::read(1).unwrap();
    let text = live_link_csv(&session.frames[TAKE_FRAMES]);
    let path = committed_take_path();
    if std::env::var_os("LIKENESS_WRITE_VIEWER_TAKE").is_some() {
        std::fs::write(&path, &text).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == text,
        "{} is not subject 1's frames {TAKE_FRAMES:?}: rewrite it with \
         LIKENESS_WRITE_VIEWER_TAKE=1 cargo test -p likeness-cli --test view",
        path.display()
    );
    let frames = read_frames(&path).unwrap();
    assert_eq!(frames.len(), TAKE_FRAMES.len());
    assert!((frames.last().unwrap().timestamp - 299.0 / 60.0).abs() < 1e-9);
}
