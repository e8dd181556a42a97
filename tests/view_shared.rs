//! Two browser tabs on one frame render at once: the viewer shares the frame's prepared scene
//! read only (each picture takes its own camera, size and view), so a tab's picture does not
//! wait for another tab's.

mod view_support;

use filmsplat::view::{App, token::Token};
use std::sync::atomic::Ordering;
use view_support::*;

/// The small bubble, its final pass at the most samples a pixel may take: a 16x16 final
/// picture of it renders for many seconds unless cancelled.
const SLOW: &str = "[input]\nsample = \"bubble\"\nparticles = 2000\n[render]\nwidth = 64\nheight = 36\nspp = 65536\n";

#[test]
fn a_second_tab_gets_its_picture_while_the_first_still_renders_the_same_frame() {
    let mut app = App::new(frames(SLOW, 1), Token::fixed(TOKEN), u64::MAX).unwrap();
    app.request_timeout = None; // the slow picture ends only when its tab cancels it
    let s = serve(app);
    let addr = s.addr;
    let slow = std::thread::spawn(move || {
        get(
            addr,
            &format!("/api/render?{CAMERA}&w=16&h=16&pass=final&client=a"),
        )
    });
    while s.stats().active.load(Ordering::SeqCst) == 0 {
        std::thread::yield_now();
    }
    // Give the slow picture a moment to get going (only makes a lock more surely seen).
    std::thread::sleep(std::time::Duration::from_millis(50));
    let other = "pos=2,0.5,1&look=0,0,0&up=0,1,0&fov=30&w=16&h=16&pass=draft";
    let b = get(addr, &format!("/api/render?{other}&client=b"));
    // Seen in the order of events: the first tab's picture is still rendering.
    let active = s.stats().active.load(Ordering::SeqCst);
    assert_eq!(b.status, 200, "{}", b.text());
    assert_eq!(active, 1, "the second tab's picture waited for the first's");
    // The first tab asks for a new picture: its slow one is cancelled.
    let again = get(
        addr,
        &format!("/api/render?{CAMERA}&w=8&h=8&pass=draft&client=a"),
    );
    assert_eq!(again.status, 200, "{}", again.text());
    let a = slow.join().unwrap();
    assert_eq!(
        a.status,
        409,
        "the slow picture ended on its own: {}",
        a.text()
    );
    // Both pictures came from one prepared variant, and the second is what it is alone.
    assert_eq!(s.stats().builds.load(Ordering::SeqCst), 1);
    let alone = get(addr, &format!("/api/render?{other}&client=b"));
    assert_eq!(decode(&b.body), decode(&alone.body));
}
