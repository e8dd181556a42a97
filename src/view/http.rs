//! A small, strict HTTP/1.1 request reader and response writer for the preview server: GET and
//! HEAD only, no bodies, bounded request line and headers, percent-decoded query strings.
//!
//! Everything a client sends is bounded before it is stored: the request line and each header
//! line at [`MAX_LINE`] bytes, all header lines together at [`MAX_HEADER_BYTES`], at most
//! [`MAX_HEADERS`] of them. A request that breaks a limit or the grammar gets a 4xx status
//! and a one-line reason, and the connection is closed.

use std::io::{BufRead, Write};

/// Longest request line or header line, bytes (the URL of a render request is ~300).
pub const MAX_LINE: usize = 8 * 1024;
/// Most bytes of all header lines together.
pub const MAX_HEADER_BYTES: usize = 32 * 1024;
/// Most header lines.
pub const MAX_HEADERS: usize = 100;
/// Most query parameters.
pub const MAX_PARAMS: usize = 64;

/// A parsed request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Request {
    /// `GET` or `HEAD`.
    pub method: String,
    /// The path, percent-decoded, without the query.
    pub path: String,
    /// The query parameters, percent-decoded, in order.
    pub query: Vec<(String, String)>,
    /// Header names (lower case) and values.
    pub headers: Vec<(String, String)>,
    /// False if the client asked to close the connection after this request (or is HTTP/1.0
    /// without keep-alive).
    pub keep_alive: bool,
}

impl Request {
    /// The first query parameter `name`.
    pub fn param(&self, name: &str) -> Option<&str> {
        self.query
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// The first header `name` (lower case).
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }
}

/// Why no request was read.
#[derive(Debug, PartialEq, Eq)]
pub enum ReadError {
    /// The client closed the connection before sending a request (normal for keep-alive).
    Closed,
    /// The request broke the grammar or a limit: answer with this status and reason, then
    /// close.
    Bad(u16, String),
}

impl ReadError {
    fn bad(status: u16, message: impl Into<String>) -> Self {
        ReadError::Bad(status, message.into())
    }
}

/// Reads one line ending in `\n` (the `\r` before it removed) of at most `max` bytes. `None`
/// at end of input before any byte.
fn read_line(r: &mut impl BufRead, max: usize) -> Result<Option<String>, ReadError> {
    let mut line = Vec::new();
    loop {
        let buf = match r.fill_buf() {
            Ok(b) => b,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) if line.is_empty() && is_timeout(&e) => return Err(ReadError::Closed),
            Err(e) if is_timeout(&e) => {
                return Err(ReadError::bad(408, "request timed out: send it whole"));
            }
            Err(_) => return Err(ReadError::Closed),
        };
        if buf.is_empty() {
            if line.is_empty() {
                return Ok(None);
            }
            return Err(ReadError::bad(400, "connection closed inside the request"));
        }
        let (used, done) = match buf.iter().position(|&b| b == b'\n') {
            Some(i) => (i + 1, true),
            None => (buf.len(), false),
        };
        if line.len() + used > max + 2 {
            return Err(ReadError::bad(
                431,
                format!("a request or header line is longer than {max} bytes"),
            ));
        }
        line.extend_from_slice(&buf[..used]);
        r.consume(used);
        if done {
            line.pop();
            if line.last() == Some(&b'\r') {
                line.pop();
            }
            return String::from_utf8(line)
                .map(Some)
                .map_err(|_| ReadError::bad(400, "the request is not UTF-8 text"));
        }
    }
}

fn is_timeout(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
    )
}

/// Reads one request: the request line, the headers, and no body (a request announcing one is
/// refused with 413, a chunked one with 501).
///
/// # Errors
/// [`ReadError::Closed`] at end of input (or a timeout) before a request;
/// [`ReadError::Bad`] with the status to answer otherwise.
pub fn read_request(r: &mut impl BufRead) -> Result<Request, ReadError> {
    // Empty lines before a request are allowed (RFC 9112 2.2).
    let line = loop {
        match read_line(r, MAX_LINE)? {
            None => return Err(ReadError::Closed),
            Some(l) if l.is_empty() => continue,
            Some(l) => break l,
        }
    };
    let mut parts = line.split(' ');
    let (Some(method), Some(target), Some(version), None) =
        (parts.next(), parts.next(), parts.next(), parts.next())
    else {
        return Err(ReadError::bad(400, "malformed request line"));
    };
    let http11 = match version {
        "HTTP/1.1" => true,
        "HTTP/1.0" => false,
        _ => {
            return Err(ReadError::bad(
                505,
                format!("unsupported version '{version}'"),
            ));
        }
    };
    let headers = read_headers(r)?;
    let header = |n: &str| {
        headers
            .iter()
            .find(|(k, _)| k == n)
            .map(|(_, v)| v.as_str())
    };
    if header("transfer-encoding").is_some() {
        return Err(ReadError::bad(501, "request bodies are not accepted"));
    }
    if let Some(len) = header("content-length")
        && len.trim() != "0"
    {
        return Err(ReadError::bad(413, "request bodies are not accepted"));
    }
    if method != "GET" && method != "HEAD" {
        return Err(ReadError::bad(
            405,
            format!("method {method} is not allowed (GET only)"),
        ));
    }
    if !target.starts_with('/') {
        return Err(ReadError::bad(400, "the request target must be a path"));
    }
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let path = percent_decode(path).ok_or_else(|| ReadError::bad(400, "malformed path"))?;
    let query = parse_query(query)?;
    let connection = header("connection").map(str::to_ascii_lowercase);
    let keep_alive = match connection.as_deref() {
        Some(c) if c.contains("close") => false,
        Some(c) if c.contains("keep-alive") => true,
        _ => http11,
    };
    Ok(Request {
        method: method.to_string(),
        path,
        query,
        headers,
        keep_alive,
    })
}

/// Header lines up to the empty line, names lower-cased.
fn read_headers(r: &mut impl BufRead) -> Result<Vec<(String, String)>, ReadError> {
    let mut headers = Vec::new();
    let mut total = 0;
    loop {
        let line = read_line(r, MAX_LINE)?
            .ok_or_else(|| ReadError::bad(400, "connection closed inside the headers"))?;
        if line.is_empty() {
            return Ok(headers);
        }
        total += line.len();
        if total > MAX_HEADER_BYTES || headers.len() >= MAX_HEADERS {
            return Err(ReadError::bad(
                431,
                format!("request headers exceed {MAX_HEADERS} lines or {MAX_HEADER_BYTES} bytes"),
            ));
        }
        let (name, value) = line
            .split_once(':')
            .filter(|(n, _)| !n.is_empty() && !n.contains([' ', '\t']))
            .ok_or_else(|| ReadError::bad(400, "malformed header line"))?;
        headers.push((name.to_ascii_lowercase(), value.trim().to_string()));
    }
}

/// `a=1&b=x%20y` → pairs, percent-decoded (`+` is a space).
fn parse_query(q: &str) -> Result<Vec<(String, String)>, ReadError> {
    let mut out = Vec::new();
    for pair in q.split('&').filter(|p| !p.is_empty()) {
        if out.len() >= MAX_PARAMS {
            return Err(ReadError::bad(
                414,
                format!("more than {MAX_PARAMS} query parameters"),
            ));
        }
        let (k, v) = pair.split_once('=').unwrap_or((pair, ""));
        let dec = |s: &str| {
            percent_decode(&s.replace('+', " "))
                .ok_or_else(|| ReadError::bad(400, "malformed query string"))
        };
        out.push((dec(k)?, dec(v)?));
    }
    Ok(out)
}

/// Decodes `%XX` escapes; `None` for a broken escape or bytes that are not UTF-8.
pub fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = s.get(i + 1..i + 3)?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// A response to write.
#[derive(Debug, Clone)]
pub struct Response {
    /// Status code.
    pub status: u16,
    /// `Content-Type`.
    pub content_type: &'static str,
    /// Extra headers.
    pub headers: Vec<(String, String)>,
    /// The body.
    pub body: Vec<u8>,
}

impl Response {
    /// A response with `body` of `content_type`.
    pub fn new(status: u16, content_type: &'static str, body: impl Into<Vec<u8>>) -> Self {
        Response {
            status,
            content_type,
            headers: Vec::new(),
            body: body.into(),
        }
    }

    /// A plain-text error: the status and a one-line reason.
    pub fn error(status: u16, message: &str) -> Self {
        Response::new(status, "text/plain; charset=utf-8", format!("{message}\n"))
    }

    /// This response with the header `name: value` added.
    pub fn with(mut self, name: &str, value: impl Into<String>) -> Self {
        self.headers.push((name.to_string(), value.into()));
        self
    }
}

/// The reason phrase of `status`.
pub fn reason(status: u16) -> &'static str {
    match status {
        200 => "OK",
        204 => "No Content",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        409 => "Conflict",
        413 => "Content Too Large",
        414 => "URI Too Long",
        422 => "Unprocessable Content",
        431 => "Request Header Fields Too Large",
        500 => "Internal Server Error",
        501 => "Not Implemented",
        503 => "Service Unavailable",
        505 => "HTTP Version Not Supported",
        _ => "Status",
    }
}

/// Writes `resp` (headers only for HEAD), with headers that keep the page to itself: no
/// caching, no sniffing, no referrer (the URL holds the token), and a content security policy
/// that allows no script, style or image from anywhere but the page itself.
pub fn write_response(
    w: &mut impl Write,
    resp: &Response,
    head_only: bool,
    keep_alive: bool,
) -> std::io::Result<()> {
    let mut head = format!(
        "HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\nCache-Control: no-store\r\n\
         X-Content-Type-Options: nosniff\r\nReferrer-Policy: no-referrer\r\n\
         Content-Security-Policy: default-src 'none'; script-src 'unsafe-inline'; \
         style-src 'unsafe-inline'; img-src 'self' blob: data:; connect-src 'self'\r\n\
         Connection: {}\r\n",
        resp.status,
        reason(resp.status),
        resp.content_type,
        resp.body.len(),
        if keep_alive { "keep-alive" } else { "close" }
    );
    for (k, v) in &resp.headers {
        head += &format!("{k}: {v}\r\n");
    }
    head += "\r\n";
    // One write: the head and the body leave in the same packets.
    let mut all = head.into_bytes();
    if !head_only {
        all.extend_from_slice(&resp.body);
    }
    w.write_all(&all)?;
    w.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(s: &str) -> Result<Request, ReadError> {
        read_request(&mut std::io::BufReader::new(s.as_bytes()))
    }

    fn status(s: &str) -> u16 {
        match parse(s) {
            Err(ReadError::Bad(st, _)) => st,
            other => panic!("{s:?} should be refused, got {other:?}"),
        }
    }

    #[test]
    fn a_get_with_a_query_is_parsed_and_decoded() {
        let r = parse("GET /api/render?token=ab&pos=1%2C2,3&t=a+b HTTP/1.1\r\nHost: x\r\n\r\n")
            .unwrap();
        assert_eq!(r.method, "GET");
        assert_eq!(r.path, "/api/render");
        assert_eq!(r.param("token"), Some("ab"));
        assert_eq!(r.param("pos"), Some("1,2,3"));
        assert_eq!(r.param("t"), Some("a b"));
        assert_eq!(r.header("host"), Some("x"));
        assert!(r.keep_alive);
        let r = parse("GET / HTTP/1.0\r\n\r\n").unwrap();
        assert!(!r.keep_alive);
        let r = parse("\r\nGET / HTTP/1.1\nConnection: close\n\n").unwrap();
        assert!(!r.keep_alive);
    }

    #[test]
    fn broken_or_oversized_requests_get_their_status() {
        assert_eq!(status("GARBAGE\r\n\r\n"), 400);
        assert_eq!(status("GET / HTTP/2.0\r\n\r\n"), 505);
        assert_eq!(status("POST / HTTP/1.1\r\n\r\n"), 405);
        assert_eq!(
            status("GET / HTTP/1.1\r\nContent-Length: 5\r\n\r\nhello"),
            413
        );
        assert_eq!(
            status("GET / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n"),
            501
        );
        assert_eq!(status("GET http://x/ HTTP/1.1\r\n\r\n"), 400);
        assert_eq!(status("GET /%zz HTTP/1.1\r\n\r\n"), 400);
        assert_eq!(status("GET /?a=%ff HTTP/1.1\r\n\r\n"), 400);
        assert_eq!(status("GET / HTTP/1.1\r\nno colon\r\n\r\n"), 400);
        assert_eq!(status("GET / HTTP/1.1\r\nHost: x\r\n"), 400);
        let long = format!("GET /{} HTTP/1.1\r\n\r\n", "a".repeat(MAX_LINE + 10));
        assert_eq!(status(&long), 431);
        let many: String = (0..MAX_HEADERS + 1)
            .map(|i| format!("h{i}: v\r\n"))
            .collect();
        assert_eq!(status(&format!("GET / HTTP/1.1\r\n{many}\r\n")), 431);
        let params: String = (0..MAX_PARAMS + 1).map(|i| format!("p{i}=1&")).collect();
        assert_eq!(status(&format!("GET /?{params} HTTP/1.1\r\n\r\n")), 414);
        assert_eq!(parse(""), Err(ReadError::Closed));
    }

    #[test]
    fn a_response_has_its_length_and_the_safety_headers() {
        let mut out = Vec::new();
        let r = Response::error(404, "no such page").with("X-A", "1");
        write_response(&mut out, &r, false, true).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.starts_with("HTTP/1.1 404 Not Found\r\n"), "{text}");
        assert!(text.contains("Content-Length: 13\r\n"), "{text}");
        assert!(text.contains("X-A: 1\r\n") && text.contains("Cache-Control: no-store"));
        assert!(text.ends_with("\r\n\r\nno such page\n"), "{text}");
        let mut head = Vec::new();
        write_response(&mut head, &r, true, false).unwrap();
        let head = String::from_utf8(head).unwrap();
        assert!(head.ends_with("\r\n\r\n") && head.contains("Connection: close"));
    }
}
