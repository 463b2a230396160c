// The picked vertex's viewpoint sphere: one point per baked viewpoint, placed where its
// camera sits (vertex - s * direction) and coloured by its baked colour.
import * as THREE from 'three';

export function makeViewpointSphere(packed, vertex, radius) {
  const [first, dirFirst, count, uniform] = packed.view.subarray(4 * vertex, 4 * vertex + 4);
  const p = packed.positions.subarray(3 * vertex, 3 * vertex + 3);
  const positions = new Float32Array(3 * count);
  const colors = new Float32Array(3 * count);
  for (let k = 0; k < count; ++k) {
    const d = packed.dirTex.subarray(4 * (dirFirst + k), 4 * (dirFirst + k) + 3);
    const c = packed.colorTex.subarray(4 * (first + (uniform ? 0 : k)), 4 * (first + (uniform ? 0 : k)) + 3);
    for (let i = 0; i < 3; ++i) {
      positions[3 * k + i] = p[i] - radius * d[i];
      colors[3 * k + i] = Math.min(1, c[i]);
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  // Linear colours: the renderer's sRGB output encodes them like the baked shader does.
  geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
  const material = new THREE.PointsMaterial({ size: 6, sizeAttenuation: false, vertexColors: true });
  const group = new THREE.Group();
  group.add(new THREE.Points(geometry, material));
  const marker = new THREE.Mesh(
    new THREE.SphereGeometry(radius * 0.08, 12, 8),
    new THREE.MeshBasicMaterial({ color: 0xffff00 }),
  );
  marker.position.set(p[0], p[1], p[2]);
  group.add(marker);
  return group;
}
