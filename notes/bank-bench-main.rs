use hyst_core::{DirectBank, Hysteresis, InverseBank, InverseHysteresis, Operator};
use std::time::Instant;
const N: usize = 1024;
const T: usize = 256;
fn main() {
    let k1 = [0.2f64; N]; let k2 = [8.0f64; N];
    let mut input = vec![0.0f64; N * T];
    for c in 0..N { for t in 0..T { let tt = t as f64 * 0.05 + c as f64 * 0.01; input[c*T+t] = 1.5*(tt).sin()*(0.37*tt).cos() + 0.3*(7.1*tt).sin(); } }
    let mut out = vec![0.0f64; N*T];
    let mut tin = vec![0.0f64; N*T]; for c in 0..N { for t in 0..T { tin[t*N+c] = input[c*T+t]; } }
    let tin32: Vec<f32> = tin.iter().map(|v| *v as f32).collect();
    let mut best = |name: &str, f: &mut dyn FnMut()| { let mut b = f64::INFINITY; for _ in 0..20 { let s = Instant::now(); f(); b = b.min(s.elapsed().as_secs_f64()); } println!("{name}: {:.3} ns/channel-sample", b*1e9/(N*T) as f64); b*1e9/(N*T) as f64 };
    let mut inv = Box::new(InverseBank::<f64, N>::new(k1, k2).unwrap());
    let bi = best("bank inverse f64", &mut || { inv.process_block(&input, &mut out, T).unwrap(); });
    best("bank inverse f64 ticks", &mut || { inv.process_ticks(&tin, &mut out).unwrap(); });
    let mut dir = Box::new(DirectBank::<f64, N>::new(k1, k2).unwrap());
    best("bank direct f64 ticks", &mut || { dir.process_ticks(&tin, &mut out).unwrap(); });
    let bd = best("bank direct f64", &mut || { dir.process_block(&input, &mut out, T).unwrap(); });
    let input32: Vec<f32> = input.iter().map(|v| *v as f32).collect(); let mut out32 = vec![0f32; N*T];
    let mut inv32 = Box::new(InverseBank::<f32, N>::new([0.2; N], [8.0; N]).unwrap());
    let bi32 = best("bank inverse f32", &mut || { inv32.process_block(&input32, &mut out32, T).unwrap(); });
    best("bank inverse f32 ticks", &mut || { inv32.process_ticks(&tin32, &mut out32).unwrap(); });
    let mut dir32 = Box::new(DirectBank::<f32, N>::new([0.2; N], [8.0; N]).unwrap());
    best("bank direct f32", &mut || { dir32.process_block(&input32, &mut out32, T).unwrap(); });
    let mut ops: Vec<_> = (0..N).map(|_| InverseHysteresis::new(0.2, 8.0).unwrap()).collect();
    let si = best("scalar inverse", &mut || { for c in 0..N { ops[c].process(&input[c*T..(c+1)*T], &mut out[c*T..(c+1)*T]).unwrap(); } });
    let mut dops: Vec<_> = (0..N).map(|_| Hysteresis::new(0.2, 8.0).unwrap()).collect();
    let sd = best("scalar direct", &mut || { for c in 0..N { dops[c].process(&input[c*T..(c+1)*T], &mut out[c*T..(c+1)*T]).unwrap(); } });
    println!("ratios: inverse {:.3}, direct {:.3}, f32/f64 inverse {:.3}", bi/si, bd/sd, bi32/bi);
}
