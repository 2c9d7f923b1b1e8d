// test_kubernetes.mjs - deploy/kubernetes checked offline: the base and the GPU overlay rendered as
// kustomize renders them (resources and JSON 6902 patches, all they use), every object validated against
// the Kubernetes schemas (npm kubernetes-models), and what Lucent needs from them checked object by
// object; where a kubectl with kustomize v3+ is installed, its rendering must give the same objects.
// Usage: node test_kubernetes.mjs REPO_ROOT   (npm packages from tests/data, installed by deploy/setup.sh)
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const root = process.argv[2];
const dataDir = path.join(root, 'tests', 'data');
const require = createRequire(path.join(dataDir, 'package.json'));
const YAML = require('yaml');
const jsonPatch = require('fast-json-patch');
let passed = 0, failed = 0;
const check = (ok, name) => { ok ? passed++ : failed++; console.log(`${ok ? 'ok  ' : 'FAIL'} ${name}`); };

function readDocs(file) {
    return YAML.parseAllDocuments(fs.readFileSync(file, 'utf8')).map((d) => d.toJS()).filter(Boolean);
}

// A kustomization: its resources (files, or directories holding a kustomization) and its patches.
function kustomize(dir) {
    const k = readDocs(path.join(dir, 'kustomization.yaml'))[0];
    const known = new Set(['apiVersion', 'kind', 'resources', 'patches']);
    const unknown = Object.keys(k).filter((key) => !known.has(key));
    if (unknown.length) throw new Error(`${dir}: this test renders resources and patches only, not ${unknown}`);
    let objects = [];
    for (const r of k.resources || []) {
        const p = path.join(dir, r);
        objects = objects.concat(fs.statSync(p).isDirectory() ? kustomize(p) : readDocs(p));
    }
    for (const patch of k.patches || []) {
        const t = patch.target;
        const targets = objects.filter((o) => o.kind === t.kind && o.metadata.name === t.name &&
            o.apiVersion === (t.group ? `${t.group}/${t.version}` : t.version));
        if (targets.length !== 1) throw new Error(`${dir}: a patch matches ${targets.length} objects`);
        jsonPatch.applyPatch(targets[0], YAML.parse(patch.patch), true, true);
    }
    return objects;
}

async function validate(obj) {
    const mod = await import(pathToFileURL(path.join(dataDir, 'node_modules', 'kubernetes-models',
                                                     obj.apiVersion, 'index.js')));
    new mod[obj.kind](obj).validate();
}

const find = (objs, kind) => objs.find((o) => o.kind === kind);
const matches = (selector, labels) => Object.entries(selector).every(([k, v]) => labels[k] === v);

const rendered = {};
for (const variant of ['base', 'overlays/gpu']) {
    const objs = kustomize(path.join(root, 'deploy', 'kubernetes', variant));
    rendered[variant] = objs;
    for (const o of objs) {
        let error = '';
        try { await validate(o); } catch (e) { error = e.message.split('\n')[0]; }
        check(!error, `${variant}: ${o.kind} ${o.metadata.name} valid against the ${o.apiVersion} schema ${error}`);
    }
}

// What Lucent needs, on the base.
const base = rendered['base'];
const dep = find(base, 'Deployment'), pod = dep.spec.template.spec, c = pod.containers[0];
const arg = (name) => (c.args.find((a) => a.startsWith(`--${name}=`)) || '').split('=')[1];
check(c.readinessProbe.httpGet.path === '/readyz' && c.livenessProbe.httpGet.path === '/healthz',
      `probes: readiness ${c.readinessProbe.httpGet.path}, liveness ${c.livenessProbe.httpGet.path}`);
const grace = pod.terminationGracePeriodSeconds, renderTimeout = Number(arg('render-timeout'));
const drain = Number(arg('drain-timeout')), preStop = Number(c.lifecycle.preStop.exec.command[1]);
check(grace > renderTimeout && grace >= preStop + drain + 5 + 2,
      `termination grace ${grace} s > render timeout ${renderTimeout} s, and >= preStop ${preStop} + drain ${drain} + worker 5 + flush 2`);
check(pod.securityContext.runAsNonRoot && c.securityContext.readOnlyRootFilesystem &&
      c.securityContext.allowPrivilegeEscalation === false && c.securityContext.capabilities.drop.includes('ALL'),
      'non-root, read-only root file system, no privilege escalation, no capabilities');
check(c.resources.requests.cpu && c.resources.requests.memory && c.resources.limits.cpu && c.resources.limits.memory,
      `resources: requests ${JSON.stringify(c.resources.requests)}, limits ${JSON.stringify(c.resources.limits)}`);
const claim = find(base, 'PersistentVolumeClaim');
const storeVolume = pod.volumes.find((v) => v.persistentVolumeClaim && v.persistentVolumeClaim.claimName === claim.metadata.name);
const storeMount = c.volumeMounts.find((m) => storeVolume && m.name === storeVolume.name);
check(claim.spec.accessModes.includes('ReadWriteMany') && storeMount && arg('store-dir').startsWith(storeMount.mountPath + '/'),
      `the store ${arg('store-dir')} on the ReadWriteMany claim ${claim.metadata.name} mounted at ${storeMount && storeMount.mountPath}`);
const tmp = c.volumeMounts.find((m) => m.mountPath === '/tmp');
check(Boolean(tmp), 'a writable /tmp beside the read-only root');
const podLabels = dep.spec.template.metadata.labels;
const svc = find(base, 'Service'), pdb = find(base, 'PodDisruptionBudget');
check(matches(svc.spec.selector, podLabels) && matches(pdb.spec.selector.matchLabels, podLabels) &&
      matches(dep.spec.selector.matchLabels, podLabels),
      'the Service, the PodDisruptionBudget and the Deployment select the pods');
const ing = find(base, 'Ingress'), backend = ing.spec.rules[0].http.paths[0].backend.service;
check(ing.metadata.annotations['nginx.ingress.kubernetes.io/upstream-hash-by'] === '$request_uri' &&
      backend.name === svc.metadata.name && svc.spec.ports.some((p) => p.name === backend.port.name),
      `Ingress: upstream-hash-by ${ing.metadata.annotations['nginx.ingress.kubernetes.io/upstream-hash-by']}, backend ${backend.name}:${backend.port.name}`);
const hpa = find(base, 'HorizontalPodAutoscaler'), metric = hpa.spec.metrics[0].pods.metric.name;
const served = fs.readFileSync(path.join(root, 'server', 'metrics.c'), 'utf8').includes(`"${metric}`);
check(hpa.spec.scaleTargetRef.name === dep.metadata.name && served && hpa.spec.minReplicas >= 2,
      `HPA on ${metric} (served by lucentd: ${served}) scales ${hpa.spec.scaleTargetRef.name} from ${hpa.spec.minReplicas}`);
check(pdb.spec.maxUnavailable === 1 && dep.spec.replicas >= 2, `PDB: at most ${pdb.spec.maxUnavailable} of ${dep.spec.replicas} down at once`);

// The GPU overlay.
const gdep = find(rendered['overlays/gpu'], 'Deployment'), gc = gdep.spec.template.spec.containers[0];
const caps = (gc.env || []).find((e) => e.name === 'NVIDIA_DRIVER_CAPABILITIES');
check(gc.resources.limits['nvidia.com/gpu'] === '1' && caps && caps.value.split(',').includes('graphics'),
      `GPU overlay: nvidia.com/gpu ${gc.resources.limits['nvidia.com/gpu']}, NVIDIA_DRIVER_CAPABILITIES ${caps && caps.value}`);

// kubectl's own kustomize, where one new enough (inline patches: kustomize v3+) is installed.
for (const variant of ['base', 'overlays/gpu']) {
    let out = null;
    try {
        out = execFileSync('kubectl', ['kustomize', path.join(root, 'deploy', 'kubernetes', variant)],
                           { encoding: 'utf8', stdio: ['ignore', 'pipe', 'ignore'] });
    } catch (e) {
        console.log(`     (kubectl kustomize ${variant} not exercised: ${e.code === 'ENOENT' ? 'no kubectl' : 'it failed or is too old'})`);
        continue;
    }
    const theirs = YAML.parseAllDocuments(out).map((d) => d.toJS()).filter(Boolean);
    const key = (o) => `${o.kind}/${o.metadata.name}`;
    const same = theirs.length === rendered[variant].length && theirs.every((t) => {
        const ours = rendered[variant].find((o) => key(o) === key(t));
        return ours && JSON.stringify(sortKeys(ours)) === JSON.stringify(sortKeys(t));
    });
    check(same, `kubectl kustomize ${variant}: the same ${theirs.length} objects`);
}

function sortKeys(v) {
    if (Array.isArray(v)) return v.map(sortKeys);
    if (v && typeof v === 'object') return Object.fromEntries(Object.keys(v).sort().map((k) => [k, sortKeys(v[k])]));
    return v;
}

console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
