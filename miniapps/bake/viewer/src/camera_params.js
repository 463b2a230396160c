// The camera of the URL (?eye=x,y,z&target=x,y,z&up=x,y,z&fov=deg&w=px&h=px), shared with
// the offline renderer's agreement test (README "Camera parameters").
export function parseViewParams(search) {
  const q = new URLSearchParams(search);
  const vec = (key) => {
    if (!q.has(key)) return null;
    const v = q.get(key).split(',').map(Number);
    if (v.length !== 3 || !v.every(Number.isFinite)) throw new Error(`URL parameter ${key}=${q.get(key)}: expected x,y,z`);
    return v;
  };
  const num = (key, check) => {
    if (!q.has(key)) return null;
    const v = Number(q.get(key));
    if (!check(v)) throw new Error(`URL parameter ${key}=${q.get(key)} is out of range`);
    return v;
  };
  return {
    map: q.get('map'),
    eye: vec('eye'),
    target: vec('target'),
    up: vec('up') ?? [0, 1, 0],
    fov: num('fov', (v) => v > 0 && v < 180) ?? 45,
    width: num('w', (v) => Number.isInteger(v) && v > 0 && v <= 8192),
    height: num('h', (v) => Number.isInteger(v) && v > 0 && v <= 8192),
    grid: q.get('grid') === '1',
  };
}
