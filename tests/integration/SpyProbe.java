// SpyProbe: runs the real lcm-spy (lcm.spy.Spy from lcm.jar) in this JVM and reports what its
// channel table shows, so a script can check that lcm-spy DECODES our channels (not only that
// it starts). Used by tests/integration/lcm_spy_check.sh; needs a display (xvfb-run).
//
//   java -cp lcm.jar:jchart2d.jar:lcmtypes.jar:DIR SpyProbe URL TYPES_JAR READY DONE TSV [PNG]
//
//  1. For every class of TYPES_JAR that implements lcm.lcm.LCMEncodable: looks its
//     LCM_FINGERPRINT up in lcm.spy.LCMTypeDatabase (the class-path scan lcm-spy itself uses to
//     name and decode a channel) and prints "type <class> ok" or "type <class> MISSING".
//  2. Starts lcm-spy (lcm.spy.Spy.main --lcm-url=URL), then creates the file READY.
//  3. Waits (at most 120 s) for the file DONE (the caller's lcm-logplayer has finished), then
//     1.5 s more, and writes the spy's channel table (columns Channel, Type, Num Msgs, Hz, 1/Hz,
//     Jitter, Bandwidth, Undecodable; tab-separated, header first) to TSV. A channel whose type
//     lcm-spy cannot name shows "?? <fingerprint>" in Type.
//  4. With PNG: a screenshot of the spy window (java.awt.Robot) written to PNG.
// Exit status 0, or 1 on any error (message on stderr).
import java.awt.Component;
import java.awt.Container;
import java.awt.Rectangle;
import java.awt.Robot;
import java.awt.Window;
import java.awt.image.BufferedImage;
import java.io.File;
import java.io.PrintWriter;
import java.util.Enumeration;
import java.util.concurrent.atomic.AtomicReference;
import java.util.jar.JarEntry;
import java.util.jar.JarFile;
import javax.imageio.ImageIO;
import javax.swing.JFrame;
import javax.swing.JTable;
import javax.swing.SwingUtilities;
import javax.swing.table.TableModel;

public class SpyProbe {
  static JTable findTable(Component c) {
    if (c instanceof JTable) return (JTable) c;
    if (c instanceof Container)
      for (Component k : ((Container) c).getComponents()) {
        JTable t = findTable(k);
        if (t != null) return t;
      }
    return null;
  }

  static String cell(Object o) { return o == null ? "" : o.toString().trim().replace('\t', ' '); }

  public static void main(String[] args) throws Exception {
    if (args.length < 5) {
      System.err.println("usage: SpyProbe URL TYPES_JAR READY DONE TSV [PNG]");
      System.exit(2);
    }
    final String url = args[0];
    final File ready = new File(args[2]), done = new File(args[3]), tsv = new File(args[4]);
    final String png = args.length > 5 ? args[5] : null;

    // 1. lcm-spy's type database knows every type of our jar by its fingerprint.
    lcm.spy.LCMTypeDatabase db = new lcm.spy.LCMTypeDatabase();
    int missing = 0;
    try (JarFile jar = new JarFile(args[1])) {
      for (Enumeration<JarEntry> e = jar.entries(); e.hasMoreElements();) {
        String n = e.nextElement().getName();
        if (!n.endsWith(".class") || n.contains("$")) continue;
        Class<?> c = Class.forName(n.substring(0, n.length() - 6).replace('/', '.'));
        if (!lcm.lcm.LCMEncodable.class.isAssignableFrom(c)) continue;
        long fp = c.getField("LCM_FINGERPRINT").getLong(null);
        boolean ok = db.getClassByFingerprint(fp) == c;
        if (!ok) missing++;
        System.out.println("type " + c.getName() + (ok ? " ok" : " MISSING"));
      }
    }

    // 2. The real lcm-spy, in this JVM.
    lcm.spy.Spy.main(new String[] {"--lcm-url=" + url});
    System.out.flush();
    if (!ready.createNewFile() && !ready.exists()) throw new RuntimeException("cannot create " + ready);

    // 3. Wait for the caller's replay, then read the channel table on the Swing thread.
    long deadline = System.currentTimeMillis() + 120_000;
    while (!done.exists()) {
      if (System.currentTimeMillis() > deadline) {
        System.err.println("SpyProbe: " + done + " did not appear within 120 s");
        System.exit(1);
      }
      Thread.sleep(100);
    }
    Thread.sleep(1500);
    final AtomicReference<JFrame> frame = new AtomicReference<>();
    final StringBuilder out = new StringBuilder();
    SwingUtilities.invokeAndWait(() -> {
      for (Window w : Window.getWindows()) {
        JTable t = findTable(w);
        if (t == null || !(w instanceof JFrame)) continue;
        frame.set((JFrame) w);
        TableModel m = t.getModel();
        for (int c = 0; c < m.getColumnCount(); c++) out.append(c > 0 ? "\t" : "").append(m.getColumnName(c));
        out.append('\n');
        for (int r = 0; r < m.getRowCount(); r++) {
          for (int c = 0; c < m.getColumnCount(); c++) out.append(c > 0 ? "\t" : "").append(cell(m.getValueAt(r, c)));
          out.append('\n');
        }
        return;
      }
    });
    if (frame.get() == null) {
      System.err.println("SpyProbe: no lcm-spy window with a channel table");
      System.exit(1);
    }
    try (PrintWriter w = new PrintWriter(tsv, "UTF-8")) { w.print(out); }

    // 4. Screenshot of the spy window.
    if (png != null) {
      final AtomicReference<Rectangle> bounds = new AtomicReference<>();
      SwingUtilities.invokeAndWait(() -> {
        frame.get().toFront();
        bounds.set(frame.get().getBounds());
      });
      Thread.sleep(500);
      BufferedImage img = new Robot().createScreenCapture(bounds.get());
      ImageIO.write(img, "png", new File(png));
    }
    System.out.flush();
    System.exit(missing == 0 ? 0 : 1);
  }
}
