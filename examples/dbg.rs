use filmsplat::optics::FilmFresnel;
use filmsplat::spectrum::{FilmLut, SpectralWeights};
fn main() {
    let lut = FilmLut::new(1.33);
    let grid: Vec<f32> = (360..=830).map(|l| l as f32).collect();
    let w = SpectralWeights::new(&grid);
    let mut rows = vec![];
    for ic in 0..200 { for ih in 0..400 {
        let cos_i = ic as f32 / 199.0; let h = ih as f32 * 10.0 + 0.7;
        let exact = w.film_reflectance_rgb(&FilmFresnel::new(cos_i, 1.33), h);
        let got = lut.reflectance_rgb(cos_i, h);
        let e = (0..3).map(|c| (exact[c]-got[c]).abs()).fold(0.0f32, f32::max);
        rows.push((e, cos_i, h));
    }}
    rows.sort_by(|a,b| b.0.partial_cmp(&a.0).unwrap());
    for r in &rows[..10] { println!("{r:?}"); }
    let t = std::time::Instant::now(); let _l = FilmLut::new(1.33); println!("build {:?}", t.elapsed());
    let n = rows.iter().filter(|r| r.1 > 0.1 && r.0 > 1e-3).count(); println!("cos>0.1 err>1e-3: {n}");
}
